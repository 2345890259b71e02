#!/usr/bin/env python3
"""Writes config/eval/commands.json: the shipped eval suite of issue 28 (contract section 15), a
list of {"domain", "command", "reference", "note"} over the three domains: the thesis' test
prompts (from config/eval/thesis.json), paraphrases of them, commands of the same shapes with
other numbers, locations and robots, and action-style commands (orders, sequences,
prohibitions), some impossible. The references are written here, one by one, from the
command's words; each is solved and checked by tests/cli/eval_test.sh (through `ctburton eval`).

With --answers FILE it also writes the script of "recorded" direct answers for
tests/tools/record_thesis (each answer is the reference itself): they let CI run the whole suite
offline; they are not a model's answers, so CI's rates say nothing about a model.

    python3 tools/make_eval_suite.py [--answers tests/recordings/suite_answers.json]
"""
import argparse
import copy
import json
import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

SR_INIT = {"robot1": "outside", "robot2": "outside", "door1": "closed", "door2": "closed", "door3": "open"}
PR_INIT = {"comp": "compOff", "conn": "disconnected", "proj": "projOff"}
AS_INIT = {"arm1": "home", "arm2": "home", "blockA": "onB", "blockB": "onC", "blockC": "onFloor"}
HOME = "arm1[i+1]==home /\\ arm2[i+1]==home"


def plan(init, goal, constraints=None, objective=None, maintenance="true"):
    p = {"initial_state": dict(init), "end_state": {"maintenance_constraint": maintenance, "goal_constraint": goal}}
    if constraints:
        p["constraints"] = constraints
    if objective:
        p["objective"] = objective
    return p


def rescue_items():
    out = []
    says = {
        "rescue": "Both robots start outside; doors 1 and 2 are closed and door 3 is open. Robot {r} must rescue person {p}.",
        "fast": "Both robots are outside the building. Robot {r} has to rescue person {p} as fast as possible.",
        "short": "Send robot {r} to rescue person {p}. The robots start outside, doors 1 and 2 closed, door 3 open.",
    }
    for kind, text in says.items():
        for r, p in [(1, 1), (2, 2), (1, 2), (2, 1)]:
            if kind != "rescue" and (r, p) in [(2, 1), (1, 2)]:
                continue
            out.append({"domain": "search_rescue", "command": text.format(r=r, p=p),
                        "reference": plan(SR_INIT, f"robot{r}[i+1]==rescuedPerson{p}",
                                          objective="makespan" if kind == "fast" else None),
                        "note": f"paraphrase ({kind})"})
    out.append({"domain": "search_rescue",
                "command": "Both robots start outside. Robot 1 rescues person 1 and robot 2 rescues person 2, as fast as possible.",
                "reference": plan(SR_INIT, "robot1[i+1]==rescuedPerson1 /\\ robot2[i+1]==rescuedPerson2", objective="makespan"),
                "note": "both persons, fixed robots"})
    out.append({"domain": "search_rescue",
                "command": "Both robots start outside. Each person must be rescued, by whichever robot; finish as early as possible.",
                "reference": plan(SR_INIT, "(robot1[i+1]==rescuedPerson1 /\\ robot2[i+1]==rescuedPerson2) \\/ (robot1[i+1]==rescuedPerson2 /\\ robot2[i+1]==rescuedPerson1)", objective="makespan"),
                "note": "paraphrase of thesis test prompt 1 (either robot)"})
    for n, ok in [(12, True), (10, False), (15, True)]:
        out.append({"domain": "search_rescue",
                    "command": f"Robots outside, doors 1 and 2 closed, door 3 open. Robot 1 must rescue person 1 within {n} seconds of the start.",
                    "reference": plan(SR_INIT, "robot1[i+1]==rescuedPerson1", {"temporal": {f"RescueWithin{n}": {
                        "accepting_event1_constraint": "robot1[i]==outside",
                        "accepting_event2_constraint": "robot1[i+1]==rescuedPerson1",
                        "lower_bound": 0, "upper_bound": n}}}),
                    "note": "deadline" + ("" if ok else " (impossible: 11 s at best)")})
    out.append({"domain": "search_rescue",
                "command": "Robot 1 rescues person 1 but door 1 must stay closed the whole time. Both robots start outside.",
                "reference": plan(SR_INIT, "robot1[i+1]==rescuedPerson1", maintenance="door1l[i]==closed"),
                "note": "maintenance"})
    # Action-style.
    acts = {"R1Opens1": {"automaton": "robot1", "command": "openDoor1"},
            "R2Opens1": {"automaton": "robot2", "command": "openDoor1"},
            "R2Opens2": {"automaton": "robot2", "command": "openDoor2"},
            "R1Opens2": {"automaton": "robot1", "command": "openDoor2"},
            "R2SetsOff1": {"automaton": "robot2", "command": "goToDoor1"},
            "R2SetsOff2": {"automaton": "robot2", "command": "goToDoor2"},
            "R1Rescues1": {"automaton": "robot1", "from": "goingDoor3Person1", "to": "rescuedPerson1"},
            "R2Enters1": {"automaton": "robot2", "command": "enterRoom1"}}

    def pick(*names):
        return {n: acts[n] for n in names}
    both = "robot1[i+1]==rescuedPerson1 /\\ robot2[i+1]==rescuedPerson2"
    items = [
        ("First robot 1 opens door 1, then robot 2 goes in through door 1. Robot 1 rescues person 1, robot 2 person 2.",
         plan(SR_INIT, both, {"actions": pick("R1Opens1", "R2Enters1"), "sequence": ["R1Opens1", "R2Enters1"]}, "makespan"), "sequence"),
        ("Robot 2 must not use door 2. Robot 1 rescues person 1 and robot 2 rescues person 2, quickly.",
         plan(SR_INIT, both, {"actions": pick("R2Opens2", "R2SetsOff2"), "forbidden": ["R2Opens2", "R2SetsOff2"]}, "makespan"), "forbidden"),
        ("Neither robot may open door 1. Robot 1 must rescue person 1 and robot 2 person 2, as fast as possible.",
         plan(SR_INIT, both, {"actions": pick("R1Opens1", "R2Opens1"), "forbidden": ["R1Opens1", "R2Opens1"]}, "makespan"), "forbidden, both robots"),
        ("Robot 2 may set off for door 1 only after robot 1 has rescued person 1. Robot 1 rescues person 1, robot 2 rescues person 2.",
         plan(SR_INIT, both, {"actions": pick("R1Rescues1", "R2SetsOff1"), "temporal": {"AfterRescue": {"event1": "R1Rescues1", "event2": "R2SetsOff1", "ordered": True}}}, "makespan"), "ordered"),
        ("Robot 2 sets off for door 1 within 2 seconds of robot 1 opening door 1, before or after. Robot 1 rescues person 1 and robot 2 person 2.",
         plan(SR_INIT, both, {"actions": pick("R1Opens1", "R2SetsOff1"), "temporal": {"Close": {"event1": "R1Opens1", "event2": "R2SetsOff1", "lower_bound": 0, "upper_bound": 2}}}, "makespan"), "either order, bounded"),
        ("Robot 1 must never open door 2; robot 1 rescues person 2.",
         plan(SR_INIT, "robot1[i+1]==rescuedPerson2", {"actions": pick("R1Opens2"), "forbidden": ["R1Opens2"]}), "forbidden"),
        ("Robot 2 never sets off for door 1 before robot 1 has opened it. Both persons rescued: robot 1 person 1, robot 2 person 2.",
         plan(SR_INIT, both, {"actions": {"R1Opens1": acts["R1Opens1"], "R2SetsOff1": dict(acts["R2SetsOff1"], occurrence="every")},
                              "temporal": {"NotBefore": {"event1": "R1Opens1", "event2": "R2SetsOff1", "ordered": True}}}, "makespan"), "every"),
        ("Only robot 2 may open doors: robot 1 must not open door 1 or door 2. Robot 1 rescues person 1.",
         plan(SR_INIT, "robot1[i+1]==rescuedPerson1", {"actions": pick("R1Opens1", "R1Opens2"), "forbidden": ["R1Opens1", "R1Opens2"]}), "forbidden, another robot helps"),
        ("Robot 1 must rescue person 1 within 11 seconds and must not open door 1 itself.",
         plan(SR_INIT, "robot1[i+1]==rescuedPerson1", {"actions": pick("R1Opens1"), "forbidden": ["R1Opens1"],
              "temporal": {"Within11": {"accepting_event1_constraint": "robot1[i]==outside", "accepting_event2_constraint": "robot1[i+1]==rescuedPerson1", "lower_bound": 0, "upper_bound": 11}}}),
         "forbidden with a deadline (impossible alone? robot 2 may open it, one second later)"),
    ]
    for cmd, ref, note in items:
        out.append({"domain": "search_rescue", "command": cmd, "reference": ref, "note": "action-style: " + note})
    return out


def presentation_items():
    out = []
    thesis = json.load(open(os.path.join(ROOT, "config/examples/presentation/test1_cot.json")))
    for on_within, stay, off in [(60, 1800, 600), (90, 600, 300), (45, 1200, 900), (60, 300, 120)]:
        ref = copy.deepcopy(thesis)
        c = ref["constraints"]
        c["episodes"]["ProjectorOnDuration"]["lower_bound"] = stay
        c["episodes"]["ProjectorOnDuration"]["upper_bound"] = stay
        c["temporal"]["ShutdownWithin600"]["lower_bound"] = off
        c["temporal"]["ShutdownWithin600"]["upper_bound"] = off
        c["temporal"]["ProjectorOnWithin60"]["upper_bound"] = on_within
        out.append({"domain": "presentation",
                    "command": f"Everything starts off and disconnected. The projector should turn on within {on_within} seconds and stay on for {stay} seconds, then everything should be off {off} seconds after that.",
                    "reference": ref, "note": "the shape of thesis test prompt 1, other numbers"})
    for text, goal, obj in [
        ("Turn the projector on. Everything starts off and disconnected.", "projl[i+1]==projOn", None),
        ("Get the projector on as fast as possible; all starts off and disconnected.", "projl[i+1]==projOn", "makespan"),
        ("Turn on the computer and the projector, as soon as possible.", "compl[i+1]==compOn /\\ projl[i+1]==projOn", "makespan"),
        ("Boot the computer. The projector stays off.", "compl[i+1]==compOn /\\ projl[i+1]==projOff", None),
        ("Connect the cable and nothing else.", "connl[i+1]==connected", None),
    ]:
        out.append({"domain": "presentation", "command": text, "reference": plan(PR_INIT, goal, objective=obj), "note": "simple goal"})
    out.append({"domain": "presentation",
                "command": "The projector must be on within 20 seconds. Everything starts off and disconnected.",
                "reference": plan(PR_INIT, "projl[i+1]==projOn", {"temporal": {"OnWithin20": {
                    "accepting_event1_constraint": "projl[i]==projOff /\\ projl[i+1]==projWarmUp",
                    "accepting_event2_constraint": "projl[i+1]==projOn", "lower_bound": 0, "upper_bound": 20}}}),
                "note": "impossible (warming up takes 30 s)"})
    acts = {"Connect": {"automaton": "conn", "command": "connect"},
            "ProjOn": {"automaton": "proj", "command": "projTurnOn"},
            "CompOn": {"automaton": "comp", "command": "compTurnOn"},
            "CompBooted": {"automaton": "comp", "from": "compBooting", "to": "compOn"},
            "ProjWarm": {"automaton": "proj", "from": "projWarmUp", "to": "projOn"}}

    def pick(*names):
        return {n: acts[n] for n in names}
    both = "compl[i+1]==compOn /\\ projl[i+1]==projOn"
    items = [
        ("Turn the computer and the projector on; the computer must have finished booting before the projector starts warming up.",
         plan(PR_INIT, both, {"actions": pick("CompBooted", "ProjOn"), "temporal": {"BootFirst": {"event1": "CompBooted", "event2": "ProjOn", "ordered": True}}}, "makespan"), "ordered"),
        ("Turn the projector on, but never the computer.",
         plan(PR_INIT, "projl[i+1]==projOn", {"actions": pick("CompOn"), "forbidden": ["CompOn"]}), "forbidden"),
        ("First connect the cable, then turn the projector on, then turn the computer on.",
         plan(PR_INIT, both, {"actions": pick("Connect", "ProjOn", "CompOn"), "sequence": ["Connect", "ProjOn", "CompOn"]}), "sequence of three"),
        ("Turn on the computer and the projector; the projector must be warm within 10 seconds of the computer finishing its boot, either way round.",
         plan(PR_INIT, both, {"actions": pick("CompBooted", "ProjWarm"), "temporal": {"Together": {"event1": "CompBooted", "event2": "ProjWarm", "lower_bound": 0, "upper_bound": 10}}}, "makespan"), "either order, bounded"),
        ("Turn the projector on only after the computer is on, and at least 60 seconds later.",
         plan(PR_INIT, both, {"actions": pick("CompBooted", "ProjOn"), "temporal": {"Later": {"event1": "CompBooted", "event2": "ProjOn", "ordered": True, "lower_bound": 60}}}, "makespan"), "ordered with a gap"),
        ("Turn on the computer and the projector, but the computer must not be turned on before the cable is connected.",
         plan(PR_INIT, both, {"actions": {"Connect": acts["Connect"], "CompOn": dict(acts["CompOn"], occurrence="every")},
                              "temporal": {"CableFirst": {"event1": "Connect", "event2": "CompOn", "ordered": True}}}), "every"),
    ]
    for cmd, ref, note in items:
        out.append({"domain": "presentation", "command": "Everything starts off and disconnected. " + cmd, "reference": ref, "note": "action-style: " + note})
    return out


def assembly_items():
    out = []
    goals = [
        ("Pick up block A and put it on the floor.", "blockA[i+1]==onFloor /\\ blockB[i+1]==onC /\\ blockC[i+1]==onFloor"),
        ("Move A to the floor and then B onto A.", "blockA[i+1]==onFloor /\\ blockB[i+1]==onA /\\ blockC[i+1]==onFloor"),
        ("Unstack everything: every block on the floor.", "blockA[i+1]==onFloor /\\ blockB[i+1]==onFloor /\\ blockC[i+1]==onFloor"),
        ("Put block A on the floor and block B on the floor, leaving C where it is.", "blockA[i+1]==onFloor /\\ blockB[i+1]==onFloor /\\ blockC[i+1]==onFloor"),
        ("Reverse the tower: C on top of B on top of A.", "blockA[i+1]==onFloor /\\ blockB[i+1]==onA /\\ blockC[i+1]==onB"),
    ]
    for text, goal in goals:
        # Reversing the tower is slow to prove under the cost objective (seconds): makespan only.
        for obj in ((None, "makespan") if "Reverse" not in text else ("makespan",)):
            cmd = "Both arms start home; A is on B, B on C, C on the floor. " + text + " Both arms end at home." + (" As fast as possible." if obj else "")
            out.append({"domain": "assembly", "command": cmd, "reference": plan(AS_INIT, HOME + " /\\ " + goal, objective=obj),
                        "note": "goal" + (" (makespan)" if obj else "")})
    acts = {"Arm1PicksA": {"automaton": "arm1", "command": "pickA"},
            "Arm2PicksA": {"automaton": "arm2", "command": "pickA"},
            "Arm1PicksB": {"automaton": "arm1", "command": "pickB"},
            "Arm2PicksB": {"automaton": "arm2", "command": "pickB"},
            "Arm2PlacesA": {"automaton": "arm2", "command": "placeAonFloor"},
            "Arm1Home": {"automaton": "arm1", "from": "placingAonFloor", "to": "home"}}

    def pick(*names):
        return {n: acts[n] for n in names}
    goal = HOME + " /\\ blockA[i+1]==onFloor /\\ blockB[i+1]==onA /\\ blockC[i+1]==onFloor"
    items = [
        ("Arm 1 must not touch block A.", {"actions": pick("Arm1PicksA"), "forbidden": ["Arm1PicksA"]}, "forbidden"),
        ("Arm 2 must not pick anything up.", {"actions": pick("Arm2PicksA", "Arm2PicksB"), "forbidden": ["Arm2PicksA", "Arm2PicksB"]}, "forbidden: one arm does it all"),
        ("Arm 1 must not pick up B.", {"actions": pick("Arm1PicksB"), "forbidden": ["Arm1PicksB"]}, "forbidden"),
        ("Arm 2 moves A; arm 1 picks up B once arm 2 starts putting A down.",
         {"actions": pick("Arm2PlacesA", "Arm1PicksB", "Arm1PicksA"), "forbidden": ["Arm1PicksA"],
          "temporal": {"AThenB": {"event1": "Arm2PlacesA", "event2": "Arm1PicksB", "ordered": True}}}, "ordered and forbidden"),
    ]
    for text, constraints, note in items:
        out.append({"domain": "assembly",
                    "command": "Both arms start home; A is on B, B on C, C on the floor. Put A on the floor and B on A, as fast as possible, arms home at the end. " + text,
                    "reference": plan(AS_INIT, goal, constraints, "makespan"), "note": "action-style: " + note})
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--answers", help="also write the record_thesis script of direct answers here")
    args = ap.parse_args()
    thesis = json.load(open(os.path.join(ROOT, "config/eval/thesis.json")))
    items = thesis + rescue_items() + presentation_items() + assembly_items()
    seen = set()
    for it in items:
        assert it["command"] not in seen, it["command"]
        seen.add(it["command"])
    with open(os.path.join(ROOT, "config/eval/commands.json"), "w") as f:
        f.write(json.dumps(items, indent=2) + "\n")
    print(f"{len(items)} items: " + ", ".join(f"{d} {sum(1 for i in items if i['domain'] == d)}" for d in ("presentation", "search_rescue", "assembly")))
    if args.answers:
        script = [{"name": f"suite_{k}", "domain": it["domain"], "prompting": "direct", "command": it["command"],
                   "answers": [{"text": json.dumps(it["reference"], indent=2)}],
                   "note": "the reference itself, written by tools/make_eval_suite.py (not a model's answer)"}
                  for k, it in enumerate(items)]
        with open(os.path.join(ROOT, args.answers), "w") as f:
            f.write(json.dumps(script, indent=2) + "\n")


if __name__ == "__main__":
    main()
