#!/usr/bin/env python3
"""Every reachable state of the assembly domain (bench/assembly_proofs.py's `assembly(blocks,
arms)`, which is config/domains/assembly.json for A, B, C and two arms) against what blocks and
arms can physically do. Exit 1 with the first violation of each kind.

    python3 tests/planner/assembly_invariants_test.py

The exploration over-approximates the runs of the contract's semantics: an arm's timed
transitions may fire at any event (durations are ignored), a block's transitions (zero duration,
automatic) fire at the very next event as the semantics forces, every guard reads the stage
before the event, and an arm whose transition does not fire issues no command (guards read the
other arms' commands only as `!=`, so that is the most permissive choice). Starting from every
block on the floor, which reaches every arrangement with the arms home. In every state reached:
  - carried: no block rests on a block that is in an arm;
  - two-on-one: no two blocks rest on one block;
  - cycle: no blocks rest on each other in a ring (A on B, B on A);
  - two-take-one: no two arms are picking or holding one block;
  - take-from-arm: no arm picks or holds a block that is in another arm;
  - take-covered: no arm picks or holds a block with another on it;
  - idle-arm: a block in an arm has that arm holding or placing it;
and at every event an arm that starts placing X has X in it, or X moves into it at that event.

The same exploration of the 3-block, 2-arm domain without the guards of the "Correction" in
bench/results/restack.md (picking X: no other arm holding X or placing onto X, nor commanded to;
placing onto Y: no other arm picking or holding Y, nor commanded to pick it) must find
violations: the check can see the race it is here for.
"""
import itertools
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "bench"))
from assembly_proofs import assembly  # noqa: E402

ATOM = re.compile(r"^(\w+?)(l|u)\[i\](==|!=)(\w+)$")


def compile_domain(dom):
    """Per automaton, its transitions as (from, to, own command or None, [(automaton index,
    'l' or 'u', equal?, value)]). Assembly guards are conjunctions of such atoms."""
    names = [a["name"] for a in dom["automata"]]
    idx = {n: i for i, n in enumerate(names)}
    out = []
    for a in dom["automata"]:
        ts = []
        for t in a["transitions"]:
            atoms, cmd = [], None
            for part in t.get("guard", "true").split(" /\\ "):
                if part == "true":
                    continue
                m = ATOM.match(part)
                assert m, part
                aut, kind, op, val = m.groups()
                if kind == "u" and aut == a["name"] and op == "==":
                    cmd = val
                else:
                    atoms.append((idx[aut], kind, op == "==", val))
            ts.append((t["from"], t["to"], cmd, atoms))
        out.append(ts)
    return names, out


def holds(atoms, loc, cmd):
    return all(((loc[a] if kind == "l" else cmd[a]) == val) == eq for a, kind, eq, val in atoms)


def check_state(names, st, flag):
    arms = {n[3:]: l for n, l in zip(names, st) if n.startswith("arm")}
    bl = {n[5:]: l for n, l in zip(names, st) if n.startswith("block")}
    for x, l in bl.items():
        if l.startswith("on") and l != "onFloor" and bl[l[2:]].startswith("inArm"):
            flag("carried", f"block{x} on {l[2:]} while block{l[2:]} is {bl[l[2:]]}")
    rests = [l for l in bl.values() if l.startswith("on") and l != "onFloor"]
    if len(rests) != len(set(rests)):
        flag("two-on-one", str(bl))
    for x in bl:
        below, seen = x, set()
        while bl[below].startswith("on") and bl[below] != "onFloor" and below not in seen:
            seen.add(below)
            below = bl[below][2:]
        if below in seen:
            flag("cycle", str(bl))
    for k, l in arms.items():
        for pre in ("picking", "holding"):
            if not l.startswith(pre):
                continue
            x = l[len(pre):]
            for j, m in arms.items():
                if j != k and m in ("picking" + x, "holding" + x):
                    flag("two-take-one", f"arm{k} {l}, arm{j} {m}")
            if bl[x].startswith("inArm") and bl[x] != "inArm" + k:
                flag("take-from-arm", f"arm{k} {l}, block{x} {bl[x]}")
            if "on" + x in bl.values():
                flag("take-covered", f"arm{k} {l}: {bl}")
    for x, l in bl.items():
        if l.startswith("inArm"):
            m = arms[l[5:]]
            if m != "holding" + x and not m.startswith(f"placing{x}on"):
                flag("idle-arm", f"block{x} {l}, arm{l[5:]} {m}")


def explore(dom):
    """(states reached, {kind: first message})."""
    names, ts = compile_domain(dom)
    arms = [i for i, n in enumerate(names) if n.startswith("arm")]
    blocks = [i for i, n in enumerate(names) if n.startswith("block")]
    start = tuple("home" if n.startswith("arm") else "onFloor" for n in names)
    seen, todo, found = {start}, [start], {}

    def flag(kind, msg):
        found.setdefault(kind, msg)

    while todo:
        s = todo.pop()
        options = [[None] + [t for t in ts[a] if t[0] == s[a]] for a in arms]
        for choice in itertools.product(*options):
            cmd = [None] * len(names)
            for a, t in zip(arms, choice):
                if t is not None:
                    cmd[a] = t[2]
            moves = {a: t for a, t in zip(arms, choice) if t is not None}
            if not all(holds(t[3], s, cmd) for t in moves.values()):
                continue
            valid = True
            for b in blocks:
                due = [t for t in ts[b] if t[0] == s[b] and holds(t[3], s, cmd)]
                if len(due) > 1:  # two transitions due at once: no valid run goes on
                    valid = False
                    break
                if due:
                    moves[b] = due[0]
            if not valid or not moves:
                continue
            ns = list(s)
            for a, t in moves.items():
                ns[a] = t[1]
            ns = tuple(ns)
            for a, t in moves.items():
                if a in arms and t[0].startswith("holding") and t[1].startswith("placing"):
                    b = names.index("block" + t[0][len("holding"):])
                    own = "inArm" + names[a][3:]
                    if own not in (s[b], ns[b]):
                        flag("place-without-block", f"{names[a]} {t[0]}->{t[1]}, "
                             f"{names[b]} {s[b]}->{ns[b]}")
            check_state(names, ns, flag)
            if ns not in seen:
                seen.add(ns)
                todo.append(ns)
    return len(seen), found


def without_the_correction(dom):
    """The domain as it was before the race was closed."""
    dom = {**dom, "automata": [dict(a) for a in dom["automata"]]}
    for a in dom["automata"]:
        if not a["name"].startswith("arm"):
            continue
        ts = []
        for t in a["transitions"]:
            if "guard" in t and t["to"].startswith("picking"):
                drop = re.compile(r"^arm\d+(l\[i\]!=(holding|placing)|u\[i\]!=place)")
            elif "guard" in t and t["to"].startswith("placing"):
                drop = re.compile(r"^arm\d+(l\[i\]!=(picking|holding)|u\[i\]!=pick)")
            else:
                ts.append(t)
                continue
            own = a["name"] + "u[i]"
            parts = [p for p in t["guard"].split(" /\\ ") if p.startswith(own) or not drop.match(p)]
            ts.append({**t, "guard": " /\\ ".join(parts)})
        a["transitions"] = ts
    return dom


def main():
    bad = 0
    for blocks, arms in (("ABC", 2), ("ABC", 3), ("ABCD", 2)):
        dom = assembly(blocks, arms)
        n, found = explore(dom)
        print(f"{blocks}, {arms} arms: {n} states, "
              f"{'no violation' if not found else 'violations: ' + ', '.join(sorted(found))}")
        for kind, msg in sorted(found.items()):
            print(f"  {kind}: {msg}")
        bad += bool(found)
    n, found = explore(without_the_correction(assembly("ABC", 2)))
    print(f"ABC, 2 arms, without the correction: {n} states, violations: "
          f"{', '.join(sorted(found))}")
    if "carried" not in found:
        print("  the check does not see the race it is here for")
        bad += 1
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
