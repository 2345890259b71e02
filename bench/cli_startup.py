#!/usr/bin/env python3
"""Process time (user + system CPU, children included) of `ctburton solve` on the thesis' examples
(issue 29 item 5: under 30 ms where no solver process is needed), and of `ctburton --help` (the
floor: loading the executable and its shared libraries).

    python3 bench/cli_startup.py [--bin build/client/ctburton] [--runs 20]

Prints a Markdown table: per example the median and the best of the runs, the status and which
engine found and proved the answer (a MiniZinc run costs a few hundred ms on its own)."""
import argparse, json, os, resource, statistics, subprocess

EXAMPLES = ["presentation/test1_cot", "presentation/test1_direct", "presentation/test2_cot",
            "search_rescue/test1", "search_rescue/test2", "assembly/test"]


def cpu_ms(cmd):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run(cmd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    used = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return used * 1000, out.stdout


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default="build/client/ctburton")
    ap.add_argument("--runs", type=int, default=20)
    a = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    print("| command | median ms | best ms | status | found by / proved by |")
    print("| --- | --- | --- | --- | --- |")
    times = [cpu_ms([a.bin, "--help"])[0] for _ in range(a.runs)]
    print(f"| `--help` | {statistics.median(times):.1f} | {min(times):.1f} | | |")
    for ex in EXAMPLES:
        domain = ex.split("/")[0]
        cmd = [a.bin, "solve", "--domain", domain, os.path.join(root, "config/examples", ex + ".json")]
        runs = [cpu_ms(cmd) for _ in range(a.runs)]
        times = [t for t, _ in runs]
        doc = json.loads(runs[-1][1])
        st = doc["stats"]
        print(f"| solve {ex} | {statistics.median(times):.1f} | {min(times):.1f} | {doc['status']} | "
              f"{st.get('found_by')} / {st.get('proved_by')} |")


if __name__ == "__main__":
    main()
