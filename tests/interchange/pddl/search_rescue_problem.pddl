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
