#!/usr/bin/env python3
"""Writes the benchmark problems into OUTDIR:
  presentation_xN.json + presentation_xN_plan.json  (thesis Table 5.1: N copies of each automaton,
      each copy with the thesis' test prompt 1 constraints, chain-of-thought version)
  search_rescue_rN.json + search_rescue_rN_plan.json (N robots, N persons: robot k rescues person k)

For teams in the hundreds (bench/teams.py) it also writes search_rescue as a template
(config/templates/search_rescue_team.json) with N robots, and state plans that say their goal once
with a quantifier (docs/formats.md, "Quantifiers"):
  rescue_team(n, persons="own")  robot k's template lists only its own person k (the coupled
      domain's other persons are dead ends for the goal "robot k rescues person k": a rescued robot
      never moves again), so the domain grows linearly with the team;
  rescue_team(n, persons=P)      the thesis' persons 1..P, every robot can reach each of them.
"""
import copy
import json
import os
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, os.path.join(ROOT, "tools"))
import gen_domains  # noqa: E402


def presentation_plan(n):
    init, goal, eps, tcs = {}, [], {}, {}
    for k in range(1, n + 1):
        s = "" if n == 1 else str(k)
        comp, conn, proj = "comp" + s, "conn" + s, "proj" + s
        init.update({comp: "compOff", conn: "disconnected", proj: "projOff"})
        goal += [f"{comp}l[i+1]==compOff", f"{conn}l[i+1]==disconnected", f"{proj}l[i+1]==projOff"]
        eps[f"ProjectorOnDuration{s}"] = {
            "accepting_constraint": f"{proj}l[i]==projOn", "state_constraint": f"{proj}l[i]==projOn",
            "lower_bound": 1800, "upper_bound": 1800}
        tcs[f"ShutdownWithin600{s}"] = {
            "accepting_event1_constraint": f"{proj}l[i]==projOn /\\ {proj}l[i+1]==projConfirm",
            "accepting_event2_constraint": f"{proj}l[i+1]==projOff /\\ {conn}l[i+1]==disconnected /\\ "
                                           f"{comp}l[i+1]==compOff /\\ "
                                           f"temporalAcceptConstraint_Traj_ShutdownWithin600{s}[i]==tempActive",
            "lower_bound": 600, "upper_bound": 600}
        tcs[f"ProjectorOnWithin60{s}"] = {
            "accepting_event1_constraint": f"{proj}l[i]==projOff /\\ {proj}l[i+1]==projWarmUp",
            "accepting_event2_constraint": f"{proj}l[i+1]==projOn",
            "lower_bound": 0, "upper_bound": 60}
    return {"initial_state": init,
            "end_state": {"maintenance_constraint": "true", "goal_constraint": " /\\ ".join(goal)},
            "constraints": {"episodes": eps, "temporal": tcs, "event": {}}}


def rescue_plan(n):
    init = {f"robot{r}": "outside" for r in range(1, n + 1)}
    init.update({"door1": "closed", "door2": "closed", "door3": "open"})
    goal = " /\\ ".join(f"robot{r}[i+1]==rescuedPerson{r}" for r in range(1, n + 1))
    return {"initial_state": init, "end_state": {"maintenance_constraint": "true", "goal_constraint": goal}}


def rescue_team(n, persons="own"):
    """search_rescue_team.json with N = n robots; persons "own" (robot k: person k) or a count P."""
    dom = json.load(open(os.path.join(ROOT, "config", "templates", "search_rescue_team.json")))
    dom["name"] = f"search_rescue_team_{n}" + ("" if persons == "own" else f"_p{persons}")
    dom["parameters"] = {"N": n}
    robot = next(a for a in dom["automata"] if a.get("template") == "robot")

    def persons_of(items):
        out = []
        for it in items:
            if isinstance(it, dict) and it.get("for") == "p":
                if persons == "own":  # the item once, for person k
                    each = it["each"] if isinstance(it["each"], list) else [it["each"]]
                    out += json.loads(json.dumps(each).replace("{p}", "{k}"))
                else:
                    it = copy.deepcopy(it)
                    it["in"] = f"1..{persons}"
                    out.append(it)
            else:
                out.append(it)
        return out

    for key in ("locations", "commands", "transitions"):
        robot[key] = persons_of(robot[key])
    if persons == "own":
        dom["description"] = ("{N} ground robots rescue {N} persons behind doors, robot k person k "
                              "(thesis 1.2.3, 5.3)")
    else:
        dom["description"] = "{N} ground robots, %d persons behind doors (thesis 1.2.3, 5.3)" % persons
    return dom


def team_initial(n):
    init = {f"robot{r}": "outside" for r in range(1, n + 1)}
    init.update({"door1": "closed", "door2": "closed", "door3": "open"})
    return init


def rescue_team_plan(n, written_out=False):
    """Robot k rescues person k, said once (or, written_out, one conjunct per robot)."""
    goal = ("every(k in robot: robot{k}l[i+1]==rescuedPerson{k})" if not written_out else
            " /\\ ".join(f"robot{r}l[i+1]==rescuedPerson{r}" for r in range(1, n + 1)))
    return {"initial_state": team_initial(n),
            "end_state": {"maintenance_constraint": "true", "goal_constraint": goal},
            "objective": "makespan"}


def some_robot_each_person_plan(n, persons):
    """Some robot at each of the persons 1..P (the other robots may stay outside)."""
    goal = f"every(p in 1..{persons}: any(k in robot: robot{{k}}l[i+1]==rescuedPerson{{p}}))"
    return {"initial_state": team_initial(n),
            "end_state": {"maintenance_constraint": "true", "goal_constraint": goal},
            "objective": "makespan"}


def main(out):
    os.makedirs(out, exist_ok=True)
    for n in (1, 2, 4, 8, 16):
        dom = gen_domains.presentation(n)
        dom["name"] = f"presentation_x{n}"
        json.dump(dom, open(f"{out}/presentation_x{n}.json", "w"), indent=1)
        json.dump(presentation_plan(n), open(f"{out}/presentation_x{n}_plan.json", "w"), indent=1)
    for n in (2, 3, 4):
        dom = gen_domains.search_rescue(n)
        dom["name"] = f"search_rescue_r{n}"
        json.dump(dom, open(f"{out}/search_rescue_r{n}.json", "w"), indent=1)
        json.dump(rescue_plan(n), open(f"{out}/search_rescue_r{n}_plan.json", "w"), indent=1)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "bench/problems")
