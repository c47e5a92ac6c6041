#!/usr/bin/env python3
"""Instruction budgets: runs tests/budgets.cpp's program under callgrind and compares each
operation's instructions per call with tests/budgets.tsv. Fails when one exceeds its budget by
more than 3 %, when one has no budget or a budget has no operation, and when a coherent query
(X.coherent) costs more than the same cold one (X.cold) and its cache's bookkeeping (1 % or
200 instructions, the larger: on a touching tick, where the cache is not used, about 150 of
12,700). Says so
when one is more than 10 % under (lower the budget in the same commit, saying why). --update
rewrites the table from this run.

usage: budgets.py PROGRAM TABLE [--update]
"""
import os
import re
import subprocess
import sys
import tempfile

OVER, UNDER = 1.03, 0.90


def measure(program):
    """{operation: instructions per call}, counted by callgrind at AVX2."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "callgrind.out")
        run = subprocess.run(
            ["valgrind", "--tool=callgrind", "--collect-atstart=no", "--callgrind-out-file=" + out, program],
            capture_output=True, text=True, env=dict(os.environ, MINKSUM_ISA="avx2"))
        if run.returncode != 0:
            sys.exit(f"budgets: {program} failed under valgrind ({run.returncode}):\n{run.stderr[-3000:]}")
        totals = {}
        for name in os.listdir(tmp):
            text = open(os.path.join(tmp, name)).read()
            desc = re.search(r"^desc: Trigger: Client Request: (\S+)", text, re.M)
            total = re.search(r"^(?:totals|summary): (\d+)", text, re.M)
            if desc and total:
                totals[desc.group(1)] = int(total.group(1))
    per_call = {}
    for line in run.stdout.splitlines():
        words = line.split()
        if len(words) == 2:
            per_call[words[0]] = totals[words[0]] / int(words[1])
        elif len(words) == 6 and words[2] == "=":  # "name calls = with - without"
            per_call[words[0]] = (totals[words[3]] - totals[words[5]]) / int(words[1])
    return per_call


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    program, table = sys.argv[1], sys.argv[2]
    measured = measure(program)
    if "--update" in sys.argv[3:]:
        with open(table, "w") as f:
            f.write("# operation\tinstructions per call (callgrind, AVX2; tests/budgets.py --update)\n")
            for op, n in measured.items():
                f.write(f"{op}\t{round(n)}\n")
        print(f"budgets: wrote {len(measured)} budgets to {table}")
        return
    budget = {}
    for line in open(table):
        if line.strip() and not line.startswith("#"):
            op, n = line.split()
            budget[op] = int(n)
    failed = []
    print(f"{'operation':36} {'budget':>12} {'measured':>12} {'change':>8}")
    for op in sorted(set(budget) | set(measured)):
        if op not in measured or op not in budget:
            failed.append(f"{op}: {'no longer measured' if op in budget else 'has no budget'}")
            continue
        change = measured[op] / budget[op]
        mark = " OVER" if change > OVER else " (under: lower the budget)" if change < UNDER else ""
        print(f"{op:36} {budget[op]:12d} {measured[op]:12.0f} {100 * (change - 1):+7.1f}%{mark}")
        if change > OVER:
            failed.append(f"{op}: {measured[op]:.0f} instructions per call, budget {budget[op]} (+3 % allowed)")
    for op in sorted(measured):
        cold = op[: -len(".coherent")] + ".cold"
        if op.endswith(".coherent") and cold in measured and measured[op] > max(1.01 * measured[cold], measured[cold] + 200):
            failed.append(f"{op}: {measured[op]:.0f} instructions per call, more than cold ({measured[cold]:.0f})")
    if failed:
        sys.exit("budgets: failed:\n  " + "\n  ".join(failed))
    print(f"budgets: {len(budget)} operations within their budgets")


if __name__ == "__main__":
    main()
