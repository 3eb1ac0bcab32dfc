#!/usr/bin/env bash
# Run the scene_parser fuzz target for a bounded time and print libFuzzer's stats.
#   fuzz/run.sh [SECONDS]   (default 60)
# Env: SANITIZER (default none; "address" also works), NICE (default 15), JOBS (default 1).
set -euo pipefail
SECONDS_TO_RUN="${1:-60}"
cd "$(dirname "$0")"
FUZZ_DIR="$PWD"
# Only stable Rust is installed: let it accept the nightly-only flags cargo-fuzz passes.
export RUSTC_BOOTSTRAP=1
CORPUS="$FUZZ_DIR/corpus/scene_parser"
mkdir -p "$CORPUS" "$FUZZ_DIR/artifacts/scene_parser"
# Seed corpus: the shipped scenes.
for f in "$FUZZ_DIR"/../assets/scenes/*.ron; do
    cp -f "$f" "$CORPUS/seed_$(basename "$f")"
done
LOG="$FUZZ_DIR/fuzz-$(date +%Y%m%d-%H%M%S).log"
echo "corpus before: $(ls "$CORPUS" | wc -l) files; log: $LOG"
set +e
nice -n "${NICE:-15}" cargo fuzz run \
    --fuzz-dir "$FUZZ_DIR" --target-dir "$FUZZ_DIR/target" \
    -s "${SANITIZER:-none}" -j "${JOBS:-1}" \
    scene_parser "$CORPUS" -- \
    -max_total_time="$SECONDS_TO_RUN" -timeout=10 -rss_limit_mb=2048 \
    -max_len=8192 -dict="$FUZZ_DIR/scene.dict" \
    -artifact_prefix="$FUZZ_DIR/artifacts/scene_parser/" \
    -print_final_stats=1 2>&1 | tee "$LOG"
rc=${PIPESTATUS[0]}
set -e
echo "---- summary ----"
grep -E '^#[0-9]+' "$LOG" | tail -1 || true
grep -E '^stat::' "$LOG" || true
echo "corpus after: $(ls "$CORPUS" | wc -l) files, $(du -sh "$CORPUS" | cut -f1)"
ls "$FUZZ_DIR/artifacts/scene_parser/" 2>/dev/null | sed 's/^/artifact: /'
echo "exit status: $rc"
exit "$rc"
