; The search-and-rescue domain of the thesis (5.3; config/domains/search_rescue.json) in PDDL 2.1:
; robots drive between places, open the doors in front of rooms, pass through open doors and
; drive to the persons. `ctburton domain import-pddl` turns it into one automaton per robot and
; per door; with search_rescue_problem.pddl it solves to the shipped domain's optimum (11 s).
(define (domain search-rescue)
  (:requirements :typing :durative-actions)
  (:types robot door place)
  (:predicates
    (at ?r - robot ?p - place)
    (closed ?d - door)
    (open ?d - door)
    (road ?from ?to - place)
    (in-front ?d - door ?p - place)
    (doorway ?d - door ?from ?to - place)
    (passage ?d - door ?from ?to - place))
  (:functions (drive-time ?from ?to - place) - number)

  (:durative-action drive
    :parameters (?r - robot ?from ?to - place)
    :duration (= ?duration (drive-time ?from ?to))
    :condition (and (at start (at ?r ?from))
                    (over all (road ?from ?to)))
    :effect (and (at start (not (at ?r ?from)))
                 (at end (at ?r ?to))))

  ; A robot in front of a closed door opens it (1 s); it stays there meanwhile.
  (:durative-action open-door
    :parameters (?r - robot ?d - door ?p - place)
    :duration (= ?duration 1)
    :condition (and (at start (closed ?d))
                    (over all (at ?r ?p))
                    (over all (in-front ?d ?p)))
    :effect (and (at start (not (closed ?d)))
                 (at end (open ?d))))

  (:action pass
    :parameters (?r - robot ?d - door ?from ?to - place)
    :precondition (and (at ?r ?from) (doorway ?d ?from ?to) (open ?d))
    :effect (and (not (at ?r ?from)) (at ?r ?to)))

  ; Through an open door and along the passage behind it, in one go.
  (:durative-action drive-through
    :parameters (?r - robot ?d - door ?from ?to - place)
    :duration (= ?duration (drive-time ?from ?to))
    :condition (and (at start (at ?r ?from))
                    (at start (open ?d))
                    (over all (passage ?d ?from ?to)))
    :effect (and (at start (not (at ?r ?from)))
                 (at end (at ?r ?to)))))
