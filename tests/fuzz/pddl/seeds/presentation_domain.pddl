; A presentation-like domain (thesis 1.2.1) with its objects as constants: a computer that boots
; and shuts down, a cable, a projector that warms up while the cable is connected.
(define (domain presentation)
  (:requirements :typing :durative-actions)
  (:types computer cable projector)
  (:constants comp - computer conn - cable proj - projector)
  (:predicates
    (comp-off ?c - computer) (comp-on ?c - computer)
    (disconnected ?k - cable) (connected ?k - cable)
    (proj-off ?p - projector) (proj-on ?p - projector))

  (:durative-action boot
    :parameters (?c - computer)
    :duration (= ?duration 15)
    :condition (at start (comp-off ?c))
    :effect (and (at start (not (comp-off ?c))) (at end (comp-on ?c))))

  (:durative-action shut-down
    :parameters (?c - computer)
    :duration (= ?duration 30)
    :condition (at start (comp-on ?c))
    :effect (and (at start (not (comp-on ?c))) (at end (comp-off ?c))))

  (:action connect
    :parameters (?k - cable ?c - computer)
    :precondition (and (disconnected ?k) (comp-off ?c))
    :effect (and (not (disconnected ?k)) (connected ?k)))

  (:action disconnect
    :parameters (?k - cable)
    :precondition (connected ?k)
    :effect (and (not (connected ?k)) (disconnected ?k)))

  (:durative-action warm-up
    :parameters (?p - projector ?k - cable)
    :duration (= ?duration 30)
    :condition (and (at start (proj-off ?p)) (over all (connected ?k)))
    :effect (and (at start (not (proj-off ?p))) (at end (proj-on ?p))))

  (:durative-action cool-down
    :parameters (?p - projector)
    :duration (and (>= ?duration 60) (<= ?duration 90))
    :condition (at start (proj-on ?p))
    :effect (and (at start (not (proj-on ?p))) (at end (proj-off ?p)))))
