#!/usr/bin/env python3
"""Generates the example domains of ../shared/design/domains.md.

    gen_domains.py OUTDIR                 write presentation.json, search_rescue.json, assembly.json
    gen_domains.py --check OUTDIR         exit 1 unless the files in OUTDIR equal the generated ones
    gen_domains.py --presentation-copies N FILE   presentation with N copies of each automaton
    gen_domains.py --robots N FILE        search_rescue with N robots and N persons
    gen_domains.py --uncertain-assembly FILE          config/uncertain/assembly.json (assembly with
                                          A's put-down on the floor taking 2 to 4 s, nature's choice)
    gen_domains.py --check-uncertain-assembly FILE    exit 1 unless FILE equals it

Every transition costs 1 (the default, so no "cost" field is written). "After N s" is an
automatic transition with duration [N, N].
"""
import json
import sys


def after(frm, to, secs):
    return {"from": frm, "to": to, "duration": [secs, secs]}


def on(frm, to, guard):
    return {"from": frm, "to": to, "guard": guard}


def presentation(copies=1):
    automata = []
    for k in range(1, copies + 1):
        sfx = "" if copies == 1 else str(k)
        comp, conn, proj = "comp" + sfx, "conn" + sfx, "proj" + sfx
        automata.append({
            "name": comp,
            "locations": ["compOff", "compBooting", "compOn", "compShutdown"],
            "commands": ["compTurnOn", "compTurnOff"],
            "transitions": [
                on("compOff", "compBooting", f"{comp}u[i]==compTurnOn"),
                after("compBooting", "compOn", 15),
                on("compOn", "compShutdown", f"{comp}u[i]==compTurnOff"),
                after("compShutdown", "compOff", 30),
            ],
        })
        automata.append({
            "name": conn,
            "locations": ["disconnected", "connected"],
            "commands": ["connect", "disconnect"],
            "transitions": [
                on("disconnected", "connected", f"{conn}u[i]==connect /\\ {comp}l[i]==compOff"),
                on("connected", "disconnected", f"{conn}u[i]==disconnect"),
            ],
        })
        automata.append({
            "name": proj,
            "locations": ["projOff", "projWarmUp", "projOn", "projConfirm", "projCoolDown"],
            "commands": ["projTurnOn", "projTurnOff"],
            "transitions": [
                on("projOff", "projWarmUp", f"{proj}u[i]==projTurnOn /\\ {conn}l[i]==connected"),
                after("projWarmUp", "projOn", 30),
                on("projOn", "projConfirm", f"{proj}u[i]==projTurnOff"),
                on("projConfirm", "projCoolDown", f"{proj}u[i]==projTurnOff"),
                after("projCoolDown", "projOff", 60),
                on("projOn", "projCoolDown", f"{conn}l[i]==disconnected"),
                on("projConfirm", "projCoolDown", f"{conn}l[i]==disconnected"),
            ],
        })
    name = "presentation" if copies == 1 else f"presentation_x{copies}"
    desc = "computer, connection and projector (thesis 1.2.1, 3.1.1)"
    if copies > 1:
        desc += f", {copies} copies of each automaton"
    return {"name": name, "description": desc, "automata": automata}


def search_rescue(robots=2):
    persons = list(range(1, robots + 1))
    names = [f"robot{r}" for r in range(1, robots + 1)]
    locations = ["outside", "goingToDoor1", "atDoor1", "door1Opening", "insideRoom1",
                 "goingToDoor3", "atDoor3"]
    locations += [f"goingDoor3Person{p}" for p in persons]
    locations += ["goingToDoor2", "atDoor2", "door2Opening", "insideRoom2"]
    locations += [f"goingRoom2Person{p}" for p in persons]
    locations += [f"rescuedPerson{p}" for p in persons]
    commands = ["goToDoor1", "openDoor1", "enterRoom1", "goToDoor3"]
    commands += [f"goToPerson{p}" for p in persons]
    commands += ["goToDoor2", "openDoor2", "enterRoom2"]
    automata = []
    for r in names:
        u = f"{r}u[i]"
        ts = [
            on("outside", "goingToDoor1", f"{u}==goToDoor1"),
            after("goingToDoor1", "atDoor1", 1),
            on("atDoor1", "door1Opening", f"{u}==openDoor1 /\\ door1l[i]==closed"),
            on("door1Opening", "insideRoom1", "door1l[i]==open"),
            on("atDoor1", "insideRoom1", f"{u}==enterRoom1 /\\ door1l[i]==open"),
            on("insideRoom1", "goingToDoor3", f"{u}==goToDoor3"),
            after("goingToDoor3", "atDoor3", 4),
        ]
        for p in persons:
            ts.append(on("atDoor3", f"goingDoor3Person{p}",
                         f"{u}==goToPerson{p} /\\ door3l[i]==open"))
            ts.append(after(f"goingDoor3Person{p}", f"rescuedPerson{p}", 5))
        ts += [
            on("outside", "goingToDoor2", f"{u}==goToDoor2"),
            after("goingToDoor2", "atDoor2", 10),
            on("atDoor2", "door2Opening", f"{u}==openDoor2 /\\ door2l[i]==closed"),
            on("door2Opening", "insideRoom2", "door2l[i]==open"),
            on("atDoor2", "insideRoom2", f"{u}==enterRoom2 /\\ door2l[i]==open"),
        ]
        for p in persons:
            ts.append(on("insideRoom2", f"goingRoom2Person{p}", f"{u}==goToPerson{p}"))
            ts.append(after(f"goingRoom2Person{p}", f"rescuedPerson{p}", 2))
        automata.append({"name": r, "locations": locations, "commands": commands,
                         "transitions": ts})
    for d in (1, 2):
        someone = " \\/ ".join(f"{r}l[i]==door{d}Opening" for r in names)
        automata.append({
            "name": f"door{d}",
            "locations": ["closed", "opening", "open"],
            "commands": [],
            "transitions": [on("closed", "opening", someone), after("opening", "open", 1)],
        })
    automata.append({"name": "door3", "locations": ["closed", "opening", "open"],
                     "commands": [], "transitions": []})
    name = "search_rescue" if robots == 2 else f"search_rescue_r{robots}"
    return {"name": name,
            "description": f"{robots} ground robots rescue persons behind doors (thesis 1.2.3, 5.3)",
            "automata": automata}


BLOCKS = ["A", "B", "C"]


def assembly():
    arms = ["arm1", "arm2"]
    arm_locs = ["home"] + [f"picking{x}" for x in BLOCKS] + [f"holding{x}" for x in BLOCKS]
    targets = {x: ["Floor"] + [y for y in BLOCKS if y != x] for x in BLOCKS}
    arm_locs += [f"placing{x}on{y}" for x in BLOCKS for y in targets[x]]
    arm_cmds = [f"pick{x}" for x in BLOCKS] + [f"place{x}on{y}" for x in BLOCKS for y in targets[x]]
    automata = []
    for k, arm in enumerate(arms):
        other = arms[1 - k]
        ts = []
        for x in BLOCKS:
            clear = [f"block{z}l[i]!=on{x}" for z in BLOCKS if z != x]
            free = [f"block{x}l[i]!=inArm1", f"block{x}l[i]!=inArm2"]
            # the other arm neither takes X (picking, or holding before X moves into it) nor
            # puts anything onto X (X would carry it away)
            parts = [f"{arm}u[i]==pick{x}"] + clear + free
            parts += [f"{other}l[i]!=picking{x}", f"{other}l[i]!=holding{x}"]
            parts += [f"{other}l[i]!=placing{z}on{x}" for z in BLOCKS if z != x]
            if k == 1:  # arm 1 has priority: not commanded to pick X or place onto X at this stage
                parts.append(f"{other}u[i]!=pick{x}")
                parts += [f"{other}u[i]!=place{z}on{x}" for z in BLOCKS if z != x]
            guard = " /\\ ".join(parts)
            ts.append(on("home", f"picking{x}", guard))
            ts.append(after(f"picking{x}", f"holding{x}", 1))
        for x in BLOCKS:
            for y in targets[x]:
                parts = [f"{arm}u[i]==place{x}on{y}"]
                if y != "Floor":
                    parts += [f"block{z}l[i]!=on{y}" for z in BLOCKS if z != y]
                    parts += [f"block{y}l[i]!=inArm1", f"block{y}l[i]!=inArm2"]
                    parts += [f"{other}l[i]!=placing{z}on{y}" for z in BLOCKS if z != y]
                    # nor is the other arm taking Y (X would leave with it)
                    parts += [f"{other}l[i]!=picking{y}", f"{other}l[i]!=holding{y}"]
                    if k == 1:  # nor commanded to place onto Y or to pick Y at this stage
                        parts += [f"{other}u[i]!=place{z}on{y}" for z in BLOCKS if z != y]
                        parts.append(f"{other}u[i]!=pick{y}")
                ts.append(on(f"holding{x}", f"placing{x}on{y}", " /\\ ".join(parts)))
                ts.append(after(f"placing{x}on{y}", "home", 2))
        automata.append({"name": arm, "locations": arm_locs, "commands": arm_cmds,
                         "transitions": ts})
    for x in BLOCKS:
        rests = ["onFloor"] + [f"on{y}" for y in BLOCKS if y != x]
        ts = []
        for k, arm in enumerate(arms, start=1):
            for y in ["Floor"] + [y for y in BLOCKS if y != x]:
                ts.append(on(f"on{y}", f"inArm{k}", f"{arm}l[i]==holding{x}"))
                ts.append(on(f"inArm{k}", f"on{y}", f"{arm}l[i]==placing{x}on{y}"))
        automata.append({"name": f"block{x}", "locations": rests + ["inArm1", "inArm2"],
                         "commands": [], "transitions": ts})
    return {"name": "assembly",
            "description": "two arms stack blocks A, B, C on a floor (thesis 1.2.2, 5.2)",
            "automata": automata}


def uncertain_assembly():
    """The shipped assembly with the return home after putting A on the floor taking 2 to 4 s
    (uniform), nature's choice, for either arm (config/uncertain/README.md)."""
    d = assembly()
    d["name"] = "assembly_uncertain"
    d["description"] += (" (uncertain: an arm that puts block A on the floor is back home after 2"
                         " to 4 s instead of 2, nature's choice: A settles on the floor before the"
                         " arm lets go)")
    for a in d["automata"]:
        for t in a["transitions"]:
            if t["from"] == "placingAonFloor" and t["to"] == "home":
                t.update(duration=[2, 4], contingent=True, distribution={"kind": "uniform"})
    return d


def dump(d):
    return json.dumps(d, indent=2) + "\n"


def standard():
    return {"presentation.json": presentation(), "search_rescue.json": search_rescue(),
            "assembly.json": assembly()}


def main(argv):
    if len(argv) == 3 and argv[0] == "--presentation-copies":
        open(argv[2], "w").write(dump(presentation(int(argv[1]))))
        return 0
    if len(argv) == 3 and argv[0] == "--robots":
        open(argv[2], "w").write(dump(search_rescue(int(argv[1]))))
        return 0
    if len(argv) == 2 and argv[0] == "--uncertain-assembly":
        open(argv[1], "w").write(dump(uncertain_assembly()))
        return 0
    if len(argv) == 2 and argv[0] == "--check-uncertain-assembly":
        if open(argv[1]).read() != dump(uncertain_assembly()):
            print(f"{argv[1]}: differs from tools/gen_domains.py --uncertain-assembly; regenerate it")
            return 1
        print("uncertain assembly matches the generator")
        return 0
    if len(argv) == 2 and argv[0] == "--check":
        bad = 0
        for name, d in standard().items():
            path = f"{argv[1]}/{name}"
            try:
                text = open(path).read()
            except OSError as e:
                print(f"{path}: {e}")
                bad += 1
                continue
            if text != dump(d):
                print(f"{path}: differs from tools/gen_domains.py output; regenerate it")
                bad += 1
        print("domain files match the generator" if not bad else f"{bad} file(s) differ")
        return 1 if bad else 0
    if len(argv) == 1:
        for name, d in standard().items():
            open(f"{argv[0]}/{name}", "w").write(dump(d))
        return 0
    print(__doc__)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
