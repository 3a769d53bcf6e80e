#!/usr/bin/env bash
# The bench programs' command lines and output folders, as `hemicontact` has them (ctest
# BenchSmoke.rules): bad values are a message and exit 1 or 2, never an abort; --help answers;
# a link planted in --out is refused, not written through; the random study's recorded commands
# keep its --set overrides and rerun each row to the same outcome; a folder named as results exists.
# Usage: check_bench_rules.sh BIN_DIR CLI SOURCE_DIR SCRATCH
set -uo pipefail
bin="$1" cli="$2" src="$3" scratch="$4"
rm -rf "$scratch" && mkdir -p "$scratch" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# expect CODE TEXT PROGRAM ARGS...: exit code CODE and TEXT on stderr or stdout.
expect() {
  local code="$1" text="$2"
  shift 2
  "$@" >"$scratch/out" 2>"$scratch/err"
  local got=$?
  [[ $got -eq $code ]] || fail "$* exited $got, expected $code: $(head -c 400 "$scratch/err")"
  grep -qF -- "$text" "$scratch/out" "$scratch/err" || fail "$*: no '$text' in: $(head -c 400 "$scratch/err")"
}

expect 2 "/dev/zero" "$bin/hemicontact_backends" --scenes /dev/zero --out "$scratch/b"
[[ ! -e "$scratch/b" ]] || fail "hemicontact_backends made its --out folder for a scene it refused"
expect 1 "--levels: expected a positive integer" "$bin/hemicontact_whole_process" --levels abc --out "$scratch/w"
expect 1 "--repeats: expected an integer from 1" "$bin/hemicontact_random_study" --repeats x --out "$scratch/r"
expect 1 "--target: expected a positive number" "$bin/hemicontact_adapt_study" --target -1 --out "$scratch/a"
for p in hemicontact_stress_report hemicontact_random_study hemicontact_backends hemicontact_whole_process \
         hemicontact_adapt_study; do
  expect 0 "usage: $p" "$bin/$p" --help
done

# A link planted where a result goes: refused naming it, the file it points at untouched.
mkdir -p "$scratch/linked" && echo "the user's" >"$scratch/victim"
ln -s "$scratch/victim" "$scratch/linked/random-default.csv"
expect 2 "random-default.csv" "$bin/hemicontact_random_study" --seeds 1 --n-max 8 --repeats 1 --out "$scratch/linked"
[[ "$(cat "$scratch/victim")" == "the user's" ]] || fail "random_study wrote through a link"

# --set kept in the Regenerate line and in every row's command, which reruns the row as it ran.
out="$scratch/random"
"$bin/hemicontact_random_study" --seeds 2 --n-max 8 --repeats 1 --set solver.exact.enabled=false --out "$out" \
  >"$scratch/study.out" 2>&1
grep -qF -- "--set solver.exact.enabled=false --repeats 1 --out DIR" "$out/random-default.md" ||
  fail "the Regenerate line drops --set: $(grep Regenerate "$out/random-default.md")"
python3 - "$out/random-default.csv" "$cli" "$src" "$scratch" <<'PY' || failures=$((failures + 1))
import csv, subprocess, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert rows, "no rows"
for r in rows:
    cmd = r["command"]
    assert "--set solver.exact.enabled=false" in cmd, cmd
    assert cmd.startswith("hemicontact solve problems/"), cmd
    rerun = sys.argv[2] + cmd[len("hemicontact"):] + " --quiet --out " + sys.argv[4] + "/rerun" + r["seed"]
    code = subprocess.run(rerun, shell=True, cwd=sys.argv[3], capture_output=True).returncode
    certified = r["outcome"] == "certified"
    assert (code == 0) == certified, f"seed {r['seed']}: row says {r['outcome']}, the rerun exited {code}"
PY

# A CSV row has the header's columns whatever its text holds: a backend named with a comma
# ("ssn (semismooth Newton, CHOLMOD)") once shifted every later column of its row.
"$bin/hemicontact_random_study" --seeds 2 --n-max 8 --repeats 1 --backend ssn --out "$scratch/random-ssn" \
  >"$scratch/study-ssn.out" 2>&1
python3 - "$scratch/random-ssn/random-default.csv" <<'PY' || failures=$((failures + 1))
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))
assert len(rows) == 3, f"{len(rows)} rows"
for r in rows[1:]:
    assert len(r) == len(rows[0]), f"{len(r)} fields, the header has {len(rows[0])}: {r}"
    assert dict(zip(rows[0], r))["solved_by"].startswith("ssn (semismooth Newton, CHOLMOD)"), r
PY

# Every folder a program names as holding results exists afterwards.
"$bin/hemicontact_adapt_study" --no-study --target 0.1 --repeats 1 --out "$scratch/adapt" >"$scratch/adapt.out" 2>&1 ||
  fail "adapt_study exited $?"
while read -r _ _ folder; do
  [[ -d "$folder" ]] || fail "adapt_study named '$folder' as results, which does not exist"
done < <(grep "^results in " "$scratch/adapt.out")

if ((failures)); then echo "$failures failure(s)"; exit 1; fi
echo "bench rules: all checks passed"
