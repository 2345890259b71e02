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

;;@@ problem
; Thesis test prompt 1 (config/examples/search_rescue/test1.json): both persons rescued, one by
; each robot, as fast as possible.
(define (problem rescue-both)
  (:domain search-rescue)
  (:objects robot1 robot2 - robot
            door1 door2 door3 - door
            outside at-door1 room1 at-door3 at-door2 room2 person1 person2 - place)
  (:init
    (at robot1 outside) (at robot2 outside)
    (closed door1) (closed door2) (open door3)
    (road outside at-door1) (= (drive-time outside at-door1) 1)
    (road outside at-door2) (= (drive-time outside at-door2) 10)
    (road room1 at-door3) (= (drive-time room1 at-door3) 4)
    (road room2 person1) (= (drive-time room2 person1) 2)
    (road room2 person2) (= (drive-time room2 person2) 2)
    (in-front door1 at-door1) (doorway door1 at-door1 room1)
    (in-front door2 at-door2) (doorway door2 at-door2 room2)
    (passage door3 at-door3 person1) (= (drive-time at-door3 person1) 5)
    (passage door3 at-door3 person2) (= (drive-time at-door3 person2) 5))
  (:goal (or (and (at robot1 person1) (at robot2 person2))
             (and (at robot1 person2) (at robot2 person1))))
  (:metric minimize (total-time)))
