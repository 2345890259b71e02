#!/usr/bin/env bash
# Black-box test of `ctburton execute` (issue 21): a plan dispatched on a fast clock with injected
# faults (from --fault and from stdin) replans and goes on to the goal; what it prints is checked
# line by line. search_rescue test2 (robot 1 must rescue person 1, optimum 11) with the optima
# after each fault worked out by hand, as in tests/planner/replan_test.cpp.
set -u
BIN=$1
SRC=$2
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cd "$SRC"
fail=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fail=$((fail + 1)); }
SP=config/examples/search_rescue/test2.json

# 0. No fault, on a clock: the presentation plan (40:30 of plan time) at 1000 times real time
# takes 2.4 s plus its solve; each transition is printed when due, in the plan's order, then the
# goal.
start=$(date +%s%N)
"$BIN" execute --domain presentation config/examples/presentation/test1_cot.json \
  --objective makespan --speed 1000 --json > "$T/plain.jsonl" 2> "$T/err.txt"
rc=$?
ms=$(( ($(date +%s%N) - start) / 1000000 ))
if [ $rc = 0 ] && [ "$ms" -ge 2400 ] && [ "$ms" -lt 120000 ] && python3 - "$T/plain.jsonl" <<'PY'
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1])]
assert [l["type"] for l in lines if l["type"] != "command"] == ["plan", "done"], lines
plan = lines[0]["answer"]
sent = [(l["time"], l["automaton"], l["from"], l["to"]) for l in lines if l["type"] == "command"]
planned = [(t["time"], t["automaton"], t["from"], t["to"]) for t in plan["transitions"]]
assert sent == planned, (sent, planned)
assert lines[-1]["goal_reached_at"] == 2430
PY
then ok "without faults every transition is dispatched when due, at --speed 1000 in $ms ms (real time: 40 min)"
else bad "without faults (rc=$rc, $ms ms)"; cat "$T/err.txt"; tail -3 "$T/plain.jsonl"; fi

# 1. While the plan runs: the robot that opens door 1 at t = 1 cannot (a fault written to stdin
# once the plan is printed, as an operator would; --speed 2). Optimal plans differ in which robot
# goes first, but either way the other robot comes to open door 1 at 2, robot 1 enters at 3, is at
# door 3 at 7 and at person 1 at 12 (by hand; tests/planner/replan_test.cpp).
python3 - "$BIN" "$SP" > "$T/block.txt" 2> "$T/err.txt" <<'PY'
import json, subprocess, sys
p = subprocess.Popen([sys.argv[1], "execute", "--domain", "search_rescue", sys.argv[2],
                      "--objective", "makespan", "--speed", "2", "--json", "--faults-stdin"],
                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
first = json.loads(p.stdout.readline())
assert first["type"] == "plan", first
plan = first["answer"]
assert plan["status"] == "optimal" and plan["objective"]["value"] == 11, plan["objective"]
opener = [t for t in plan["transitions"] if t["to"] == "door1Opening"]
assert len(opener) == 1 and opener[0]["time"] == 1, opener
who = opener[0]["automaton"]
p.stdin.write(f"block:{who}:atDoor1:door1Opening@1\n")
p.stdin.close()
lines = [first] + [json.loads(l) for l in p.stdout]
assert p.wait() == 0
faults = [l for l in lines if l["type"] == "fault"]
assert [(f["time"], f["fault"]) for f in faults] == [(1, f"block:{who}:atDoor1:door1Opening@1")], faults
replans = [l for l in lines if l["type"] == "replan"]
assert len(replans) == 1 and replans[0]["time"] == 1, replans
re = replans[0]["answer"]
assert re["status"] == "optimal" and re["verified"] and re["objective"]["value"] == 12, re["objective"]
assert re["now"] == 1
# The history sent: what was dispatched before 1 (the opener set off at 0), marked executed.
assert [(t["automaton"], t["to"], t["time"]) for t in re["transitions"] if t.get("executed")] == \
    [(who, "goingToDoor1", 0)], re["transitions"]
assert any(d["automaton"] == who and d.get("command") == "openDoor1" for d in re["diff"]["dropped"]), re["diff"]
# What was dispatched: in time order, the opener never opens door 1, the other robot does, at 2.
cmds = [l for l in lines if l["type"] == "command"]
times = [c["time"] for c in cmds]
assert times == sorted(times), times
assert not any(c["automaton"] == who and c["to"] == "door1Opening" for c in cmds), cmds
assert any(c["automaton"] != who and c["command"] == "openDoor1" and c["time"] == 2 for c in cmds), cmds
assert cmds[-1]["to"] == "rescuedPerson1" and cmds[-1]["time"] == 12, cmds[-1]
assert lines[-1] == {"type": "done", "goal_reached_at": 12}, lines[-1]
print(who)
PY
rc=$?
if [ $rc = 0 ]; then ok "the robot opening door 1 cannot ($(cat "$T/block.txt")): replanned at 1, the other opens it, goal 11 -> 12"
else bad "a blocked move while the plan runs"; cat "$T/err.txt"; fi

# 2. As text, from --fault: robot 1 cannot set off to door 1 (before it does, at 0). It goes
# through door 2: there at 10, opens it (1 s), person 1 two seconds later: 13.
"$BIN" execute --domain search_rescue "$SP" --objective makespan --speed 100 \
  --fault block:robot1:outside:goingToDoor1@0 > "$T/door2.txt" 2> "$T/err.txt"
rc=$?
if [ $rc = 0 ] && grep -q "^t=     0.0  PLAN optimal, makespan 11$" "$T/door2.txt" &&
   grep -q "^t=     0.0  FAULT block:robot1:outside:goingToDoor1@0$" "$T/door2.txt" &&
   grep -Eq "^t=     0.0  REPLAN optimal, makespan 13 \(kept [0-9]+, moved [0-9]+, added [1-9][0-9]*, dropped [1-9][0-9]*\)$" "$T/door2.txt" &&
   grep -q "^t=     0.0  robot1  goToDoor2  outside -> goingToDoor2$" "$T/door2.txt" &&
   ! grep -q "robot1  goToDoor1" "$T/door2.txt" &&
   tail -1 "$T/door2.txt" | grep -q "^goal reached at t = 13 s$"; then
  ok "a fault from --fault, in text: PLAN, FAULT, REPLAN (13, through door 2), the commands, the goal"
else bad "a fault from --fault, in text (rc=$rc)"; cat "$T/door2.txt" "$T/err.txt"; fi

# 3. A delay: robot 1's first move comes 3 s late. It is held, dispatched when it comes (at L,
# 3 s after its planned time), and the run replans then. From there robot 1 needs at least
# 1 + 4 + 5 = 10 s (door 1 already open) and at most 11 (it opens the door itself).
"$BIN" execute --domain search_rescue "$SP" --objective makespan --speed 100 --json \
  --fault delay:robot1:3 > "$T/delay.jsonl" 2> "$T/err.txt"
rc=$?
if [ $rc = 0 ] && python3 - "$T/delay.jsonl" <<'PY'
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1])]
plan = lines[0]["answer"]
planned = min(t["time"] for t in plan["transitions"] if t["automaton"] == "robot1")
late = [l for l in lines if l["type"] == "late"]
L = planned + 3
assert [(l["automaton"], l["from"], l["to"], l["time"]) for l in late] == [("robot1", "outside", "goingToDoor1", L)], late
replans = [l for l in lines if l["type"] == "replan"]
assert len(replans) == 1 and replans[0]["time"] == L, replans
re = replans[0]["answer"]
assert re["status"] == "optimal" and re["verified"], re["status"]
assert any(t.get("executed") and t["automaton"] == "robot1" and t["time"] == L for t in re["transitions"])
goal = lines[-1]["goal_reached_at"]
assert lines[-1]["type"] == "done" and goal == re["objective"]["value"] and L + 10 <= goal <= L + 11, (goal, L)
PY
then ok "a delay holds the move, replans when it comes and reaches the goal"
else bad "a delay (rc=$rc)"; cat "$T/err.txt"; tail -5 "$T/delay.jsonl"; fi

# 4. Both of robot 1's ways out blocked before it leaves: the goal cannot be reached. The replan
# is infeasible, its explanation names both blocked moves, and execute exits 1.
"$BIN" execute --domain search_rescue "$SP" --objective makespan --speed 0 \
  --fault block:robot1:outside:goingToDoor1@0 --fault block:robot1:outside:goingToDoor2@0 \
  > "$T/stuck.txt" 2> "$T/err.txt"
rc=$?
if [ $rc = 1 ] && grep -q "REPLAN infeasible" "$T/stuck.txt" && grep -q "(/blocked/0)" "$T/stuck.txt" &&
   grep -q "(/blocked/1)" "$T/stuck.txt" && ! grep -q "goal reached" "$T/stuck.txt"; then
  ok "an unreachable goal after the faults: REPLAN infeasible naming /blocked/0 and /blocked/1, exit 1"
else bad "an unreachable goal (rc=$rc)"; cat "$T/stuck.txt" "$T/err.txt"; fi

# 5. A bad fault is a usage error.
"$BIN" execute --domain search_rescue "$SP" --fault explode:robot1 > /dev/null 2> "$T/err.txt"
rc=$?
if [ $rc = 2 ] && grep -q "expected delay:AUTOMATON:SECONDS" "$T/err.txt"; then ok "a bad --fault exits 2 and says what is expected"
else bad "a bad --fault (rc=$rc)"; cat "$T/err.txt"; fi

# 6. Simulated executions of a flexible plan (contract section 13): nature draws the warm-up;
#    the dynamic dispatcher never breaks the "on exactly 10 s" plan, fixed times mostly do; with
#    --json each run's realized trajectory is a line, and the totals come last.
U=config/uncertain
out=$("$BIN" execute --domain $U/presentation.json $U/on_ten_then_off.json --sample distribution \
      --runs 300 --seed 3); rc=$?
if [ $rc = 0 ] && [ "$out" = '{"runs":300,"succeeded":300,"violated":0}' ]; then
  ok "300 dynamic executions of a dynamically controllable plan: no violation"
else bad "dynamic executions (rc=$rc): $out"; fi
out=$("$BIN" execute --domain $U/presentation.json $U/on_ten_then_off.json --sample uniform \
      --runs 300 --seed 3 --dispatch fixed); rc=$?
if [ $rc = 5 ] && python3 -c "import json,sys; d=json.loads(sys.argv[1]); assert d['runs']==300 and d['violated']>200, d" "$out"; then
  ok "fixed-time dispatch of the same plan breaks most runs (exit 5): $out"
else bad "fixed-time dispatch (rc=$rc): $out"; fi
"$BIN" execute --domain $U/presentation.json $U/on_ten_then_off.json --sample uniform --runs 5 \
  --seed 9 --json > "$T/runs.jsonl"; rc=$?
if [ $rc = 0 ] && python3 - "$T/runs.jsonl" <<'PY'
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1])]
assert len(lines) == 6, len(lines)
for r in lines[:5]:
    t = r["trajectory"]
    assert r["succeeded"] and t["events"][0] == 0, r
    on = next(x["time"] for x in t["transitions"] if x["to"] == "projOn")
    off = next(x["time"] for x in t["transitions"] if x["to"] == "projConfirm")
    assert 20 <= on <= 40 and off == on + 10, (on, off)
assert lines[5] == {"runs": 5, "succeeded": 5, "violated": 0}, lines[5]
PY
then ok "--json: five realized trajectories (off 10 s after on, on within 20-40 s) and the totals"
else bad "--json runs (rc=$rc)"; cat "$T/runs.jsonl"; fi
out=$("$BIN" execute --domain $U/presentation.json $U/together_within_5.json --sample uniform --runs 3 \
  --time-limit-ms 2000 2>&1); rc=$?
if [ $rc = 3 ] && [[ "$out" == *"not dynamically controllable"* ]]; then
  ok "a plan that is not controllable is not executed (exit 3) unless --controllability none"
else bad "uncontrollable plan (rc=$rc): $out"; fi

# --server: the execution runs in a real `ctburton serve` on its simulated team (contract 14);
# "Rescue person 1 fast" with 30 % of moves failing and seed 2 fails one move, replans and
# succeeds; the events come back one JSON object a line, then the summary; exit 0.
. "$SRC/tests/cli/serve.sh"
start_server "$T/data" "$T/serve.log"
cat > "$T/fast.json" <<'JSON'
{"initial_state": {"robot1": "outside", "robot2": "outside", "door1": "closed", "door2": "closed", "door3": "open"},
 "end_state": {"maintenance_constraint": "true", "goal_constraint": "robot1[i+1]==rescuedPerson1"},
 "objective": "makespan"}
JSON
"$BIN" execute --server "http://127.0.0.1:$PORT" --domain search_rescue "$T/fast.json" --speed 50 \
  --fail 0.3 --seed 2 --json > "$T/server.jsonl" 2> "$T/server_err.txt"
rc=$?
if [ $rc = 0 ] && python3 - "$T/server.jsonl" <<'PY'
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1])]
events = [l["event"] for l in lines[:-1]]
assert events[0] == "dispatched" and events[-1] == "finished", events
assert "replanned" in events and any(l["event"] == "reported" and "failed" in l["data"] for l in lines[:-1]), events
assert lines[-1]["state"] == "succeeded" and lines[-1]["replans"] == 1, lines[-1]
PY
then ok "--server: the server carries it out, a failed move replans, succeeded (exit 0)"
else bad "--server (rc=$rc)"; cat "$T/server.jsonl" "$T/server_err.txt"; fi
out=$("$BIN" execute --server "http://127.0.0.1:$PORT" --domain nosuch "$T/fast.json" 2>&1); rc=$?
if [ $rc = 3 ] && [[ "$out" == *"nosuch"* ]]; then ok "--server with an unknown domain: the server's error"
else bad "--server unknown domain (rc=$rc): $out"; fi
kill $SERVER; wait $SERVER 2>/dev/null

exit $fail
