#!/usr/bin/env bash
# Build and run the libFuzzer harness of the C core (see README.md here).
#
#   bench/fuzz/run.sh [SECONDS [JOBS]]      default: 600 s, 1 job
#
# Environment: CC (default clang), CSRC (default csrc/ of this tree),
# FUZZ_DIR (default build/fuzz: binary, corpus, crash artifacts, log).
# Exit status 0 when the run ended without a finding; otherwise 1 and the
# reproducer files are listed (run one with: $FUZZ_DIR/fuzz_core FILE).
# Fork mode: the run goes on after a crash, so it collects every distinct one.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
SECONDS_TO_RUN="${1:-600}"
JOBS="${2:-1}"
CC="${CC:-clang}"
CSRC="${CSRC:-$ROOT/csrc}"
OUT="${FUZZ_DIR:-$ROOT/build/fuzz}"
command -v "$CC" >/dev/null || { echo "fuzz: $CC not found (apt-get install -y clang)" >&2; exit 2; }
# findings are per run (the corpus is kept and grows from run to run)
rm -rf "$OUT/artifacts" "$OUT"/fuzz-*.log
mkdir -p "$OUT/corpus" "$OUT/artifacts"

GSL_CFLAGS="$(pkg-config --cflags gsl 2>/dev/null || gsl-config --cflags)"
GSL_LIBS="$(pkg-config --libs gsl 2>/dev/null || gsl-config --libs)"
echo "fuzz: building $OUT/fuzz_core from $CSRC/*.c"
# -O1 -g: readable stacks; -fno-sanitize-recover: every UBSan report is a crash.
"$CC" -std=c99 -D_GNU_SOURCE -g -O1 -fno-omit-frame-pointer \
    -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
    -I"$CSRC" -I"$ROOT/csrc" $GSL_CFLAGS \
    "$ROOT/bench/fuzz/fuzz_core.c" "$CSRC"/*.c $GSL_LIBS -lm -o "$OUT/fuzz_core"

# a few seeds: empty scene, one tendon, two tendons with loads, closed forms
printf '\x01\x00' > "$OUT/corpus/seed_rod"
printf '\x01\x01\x04\x00\x10\x20\x00\x50\x40\x40\x40\x40\x40\x00\x00\x40\x40\x40\x40' > "$OUT/corpus/seed_tendon"
printf '\x01\x0a\x31\x00\x10\x20\x00\x50\x40\x40\x40\x40\x40\x00\x01\x40\x40\x40\x40\x00\x40\x40\x40\x40' > "$OUT/corpus/seed_two"
printf '\x00\x40\x40\x40\x40\x40\x40\x40\x40\x40\x04\x40' > "$OUT/corpus/seed_closed"

echo "fuzz: running for $SECONDS_TO_RUN s ($JOBS job(s)); log in $OUT/fuzz.log"
set +e
(cd "$OUT" && ASAN_OPTIONS="detect_leaks=1:abort_on_error=1" \
    UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1" \
    ./fuzz_core -max_total_time="$SECONDS_TO_RUN" -timeout=10 -rss_limit_mb=2048 \
        -print_final_stats=1 -artifact_prefix="$OUT/artifacts/" \
        -fork="$JOBS" -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
        corpus 2>&1) > "$OUT/fuzz.log"
rc=$?
set -e
# fork mode (-fork=JOBS -ignore_crashes=1) keeps fuzzing after a finding, so one
# run collects every distinct crash/timeout; the last status line has the totals
grep -E "^#[0-9]+: cov:" "$OUT/fuzz.log" | tail -1 || true
found=$(ls "$OUT/artifacts" 2>/dev/null | wc -l)
echo "fuzz: exit $rc, corpus $(ls "$OUT/corpus" | wc -l) inputs, findings $found"
if [ "$found" -gt 0 ] || [ "$rc" -ne 0 ]; then
    ls -l "$OUT/artifacts"
    grep -hE "contract violation|ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error" \
        "$OUT/fuzz.log" "$OUT"/fuzz-*.log 2>/dev/null | sed 's/==[0-9]*==//' | sort | uniq -c | head -20
    exit 1
fi
