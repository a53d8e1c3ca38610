#!/usr/bin/env bash
# One command for a GPU machine (issue 24): builds FIRD (Release), runs the test suite with
# the Vulkan validation layers on the real driver, then measures one table and writes it
# to a markdown file:
#   - Models A, B and C at the paper's ray counts (the scenes' own): the whole evaluation of
#     a candidate and each pass in ms (fird bench --candidates), beside the paper's Table 3
#     (height map / intersection search / error calculation: 56/976/277, 34/2963/278,
#     86/2406/263 ms on its 2010 GPU);
#   - ray-bounces per second of the bounce loop (fird trace --profile);
#   - the per-candidate time at 1e6 rays, alone and in batches of 16 (Evaluator::evaluate_batch);
#   - the search time of fird optimize (auto) on Model A;
#   - the workbench's frame time p50/p99 while a search runs (offscreen: no display needed).
#
# Usage: scripts/gpu_check.sh [--quick] [--no-build] [--no-tests] [--fird PATH] [--device NAME]
#                             [--out FILE]
#   --quick     the same table at a hundredth of the rays, no test suite (any device,
#               lavapipe included): the script itself checked before a GPU is at hand
#   --no-build  use build/release as it is (a machine without Debian's packages, say)
#   --no-tests  skip the test suite
#   --fird      the fird binary to measure (default build/release/app/fird; implies --no-build)
#   --device    the Vulkan device (fird --device: a substring of its name)
#   --out       the markdown file (default: gpu_check.md in the working directory)
# Every step is bounded by a timeout (at most GPU_CHECK_STEP_LIMIT_S seconds where that is
# set: a lease of device time); a step that fails or times out is reported in the table as
# such and the script goes on (exit 1 at the end if any did).
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
quick=0 build=1 tests=1 device="" out="$PWD/gpu_check.md" fird="$root/build/release/app/fird"
while (($#)); do
  case "$1" in
    --quick) quick=1; tests=0 ;;
    --no-build) build=0 ;;
    --no-tests) tests=0 ;;
    --fird) fird="${2:?--fird needs a path}"; build=0; shift ;;
    --device) device="${2:?--device needs a name}"; shift ;;
    --out) out="${2:?--out needs a file}"; shift ;;
    -h|--help) sed -n '2,24p' "$0"; exit 0 ;;
    *) echo "gpu_check.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
case "$out" in /*) ;; *) out="$PWD/$out" ;; esac
# Debian's python3 where there is one (the tables need only its standard library).
py=/usr/bin/python3; [ -x "$py" ] || py=python3
scale=1; ((quick)) && scale=100
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
failed=0
start_s=$(date +%s)

note() { echo "gpu_check: $*" >&2; }
step() { # NAME TIMEOUT_S COMMAND...: runs bounded, logs to $work/NAME.log, returns its status
  local name="$1" limit="$2"
  shift 2
  [ -n "${GPU_CHECK_STEP_LIMIT_S:-}" ] && ((GPU_CHECK_STEP_LIMIT_S < limit)) && limit=$GPU_CHECK_STEP_LIMIT_S
  note "$name"
  timeout "$limit" "$@" >"$work/$name.out" 2>"$work/$name.log"
  local rc=$?
  if ((rc != 0)); then
    failed=1
    note "$name failed (exit $rc; 124: timed out after $limit s): $(tail -1 "$work/$name.log")"
  fi
  return $rc
}

if ((build)); then
  step build 1800 "$root/scripts/setup.sh" release || { cat "$work/build.log" >&2; exit 1; }
fi
[ -x "$fird" ] || { echo "gpu_check.sh: no $fird (build first, or drop --no-build)" >&2; exit 1; }
dev=(); [ -n "$device" ] && dev=(--device "$device")

suite="not run"
if ((tests)); then
  if step tests 1800 bash -c "cd '$root/build/release' && FIRD_VALIDATION=1 ctest -j $(nproc) --output-on-failure ${FIRD_GPU_CHECK_CTEST_ARGS:-}"; then
    suite="passed: $(grep -Eo '[0-9]+ tests passed|tests passed, [0-9]+ tests failed out of [0-9]+' "$work/tests.out" | tail -1)"
  else
    suite="FAILED: $(grep -E 'tests passed|tests failed' "$work/tests.out" | tail -1)"
  fi
fi

# Per scene: the candidate at the scene's rays / scale, at 1e6 / scale, and the profile.
declare -A rays=([A]=10000000 [B]=5000000 [C]=10000000)
for m in A B C; do
  scene="$root/scenes/model_${m,,}.toml"
  n=$((rays[$m] / scale))
  step "cand_$m" 900 "$fird" "${dev[@]}" bench --candidates --rays "$n" --reps 3 --batch 1 --out "$work/cand_$m" "$scene"
  step "cand1e6_$m" 600 "$fird" "${dev[@]}" bench --candidates --rays $((1000000 / scale)) --reps 5 --batch 16 --out "$work/cand1e6_$m" "$scene"
  step "profile_$m" 600 "$fird" "${dev[@]}" trace "$scene" --rays "$n" --json --profile
  cp "$work/profile_$m.out" "$work/profile_$m.json" 2>/dev/null
done
stages="1e5,1e6,1e7"; ((quick)) && stages="1e3,1e4,1e5"
step search_A 1200 "$fird" "${dev[@]}" optimize "$root/scenes/model_a.toml" --json --rays "$stages" --seed 1
# The workbench with no window (fird gui --offscreen): its frames drawn into an image on the
# frames' queue, so a machine without a display (a data-centre GPU's) measures it too.
frames="failed (see the log above)"
script="$root/scripts/workbench_latency.fird"
if step workbench 900 "$fird" "${dev[@]}" gui --offscreen 1440x900 --script "$script" --stats; then
  frames="$("$py" - "$work/workbench.out" <<'PY' 2>/dev/null || echo "unreadable stats"
import json, sys
j = json.load(open(sys.argv[1]))
print(f"p50 {j['frame_ms_p50']:.1f} ms, p99 {j['frame_ms_p99']:.1f} ms over {j['frames']} frames "
      f"(build p99 {j['build_ms_p99']:.1f} ms, draw p99 {j['present_ms_p99']:.1f} ms), "
      f"{j['evaluations']} evaluations in the session, worker on "
      f"{'a queue of its own' if j.get('separate_work_queue') else 'the frames queue'}")
PY
)"
fi
device_name="$("$fird" "${dev[@]}" info 2>/dev/null | sed -n 's/^chosen: //p' | head -1)"
compute_queue="$("$fird" "${dev[@]}" info 2>/dev/null | sed -n 's/^compute queue: //p' | head -1)"

"$py" - "$work" "$out" "$quick" "$suite" "$frames" "$device_name" "$(($(date +%s) - start_s))" "$compute_queue" <<'EOF'
import csv, json, os, sys
work, out, quick, suite, frames, device, elapsed, compute_queue = sys.argv[1:]
quick = quick == "1"
paper = {"A": (56, 976, 277), "B": (34, 2963, 278), "C": (86, 2406, 263)}

def candidates(name):
    try:
        with open(os.path.join(work, name, "candidates.csv")) as f:
            return next(csv.DictReader(f))
    except (OSError, StopIteration):
        return None

def number(row, key, fmt="{:.1f}"):
    return fmt.format(float(row[key])) if row and row.get(key) not in (None, "") else "failed"

def bounces_per_s(m):
    try:
        j = json.load(open(os.path.join(work, f"profile_{m}.json")))
        rays = sum(p["rays"] for p in j["profile"])
        ms = sum(p["trace_ms"] for p in j["profile"])
        return f"{rays / (ms / 1e3):.3g}" if ms > 0 else "–"
    except (OSError, ValueError, KeyError):
        return "failed"

lines = [f"# FIRD GPU check{' (--quick: a hundredth of the rays)' if quick else ''}", "",
         f"Device: {device or 'unknown'}. Compute queue: {compute_queue or 'unknown'}. "
         f"Test suite with validation: {suite}. "
         f"Wall time of the check: {elapsed} s.", "",
         "| model | rays | evaluation ms | height field ms | trace ms | histogram ms | compare ms | "
         "paper: height map / search / error ms | submissions per evaluation | ray-bounces/s | "
         f"candidate ms at {'1e4' if quick else '1e6'} rays | in batches of 16 |",
         "|---|---|---|---|---|---|---|---|---|---|---|---|"]
for m in "ABC":
    c, c1 = candidates(f"cand_{m}"), candidates(f"cand1e6_{m}")
    lines.append(
        f"| {m} | {c['rays'] if c else 'failed'} | {number(c, 'candidate_ms')} | "
        f"{number(c, 'heightfield_ms')} | {number(c, 'trace_ms')} | {number(c, 'histogram_ms')} | "
        f"{number(c, 'compare_ms')} | {' / '.join(map(str, paper[m]))} | "
        f"{number(c, 'submissions', '{:.0f}')} | {bounces_per_s(m)} | "
        f"{number(c1, 'candidate_ms', '{:.2f}')} | {number(c1, 'batch_candidate_ms', '{:.2f}')} |")
try:
    t = open(os.path.join(work, "search_A.out")).read()
    s = json.JSONDecoder().raw_decode(t[t.index("{"):])[0]
    search = (f"{s['time_s']:.1f} s, {s['evaluations']} evaluations, final l2 / noise floor "
              f"{s['final_l2'] / s['noise_floor_l2']:.3f}" if s.get("noise_floor_l2") else f"{s['time_s']:.1f} s")
except (OSError, ValueError, KeyError):
    search = "failed"
lines += ["", f"Search of Model A (fird optimize, auto, stages {'1e3,1e4,1e5' if quick else '1e5,1e6,1e7'} rays, "
          f"seed 1): {search}.", "",
          f"Workbench while a search of Model A runs (scripts/workbench_latency.fird, offscreen 1440 x 900): {frames}.", ""]
text = "\n".join(lines)
tmp = out + ".tmp"
with open(tmp, "w") as f:
    f.write(text)
os.replace(tmp, out)  # whole or not at all
print(text)
EOF
note "wrote $out"
exit $failed
