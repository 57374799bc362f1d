#!/usr/bin/env bash
# Adds to .gpu/ (where the workplace's bench-packing script put the benchmark, the scenes and the
# Vulkan loader packages; run it first) the pass-by-pass diagnostics issue 39 leaves for a GPU:
# a `render` built with docs/bench/passes-split-marks.patch (each step of the compute chain
# marked; PULL_BACK and DEPTH32 knobs) and docs/bench/blur-workgroup-cache.patch
# (PENUMBRA_BLUR_CACHE=1: the blur reading its tile and apron from workgroup memory), and
# .gpu/diag.sh, which times the A/B pairs the library's environment switches give in that one
# binary. The patches are applied to this checkout's working tree for the build and taken off
# again (the tree must have no changes of its own); target/release/examples/render is then the
# patched build until the next build of it.
#
# Here:            bash tools/pack-gpu-diag.sh       (after the benchmark is packed into .gpu/)
# On the GPU:      bash .gpu/diag.sh OUT_DIR         (about 3 minutes; then .gpu/run.sh)
set -euo pipefail
root=$(git rev-parse --show-toplevel); cd "$root"
if ! git diff --quiet || ! git diff --cached --quiet; then
  echo "pack-gpu-diag: the working tree has changes; commit or stash them first" >&2
  exit 1
fi
if [ ! -d .gpu/debs ] || [ ! -f .gpu/run.sh ]; then
  echo "pack-gpu-diag: no packed benchmark in .gpu/: run the workplace's bench-packing script first" >&2
  exit 1
fi
patches=(docs/bench/passes-split-marks.patch docs/bench/blur-workgroup-cache.patch)
git apply "${patches[@]}"
trap 'git apply -R "${patches[@]}"' EXIT
cargo build --locked --release --example render
cp target/release/examples/render .gpu/render-split
strip .gpu/render-split 2>/dev/null || true
cat > .gpu/diag.sh <<'DIAG'
#!/usr/bin/env bash
# On the GPU machine, from the checkout's root: bash .gpu/diag.sh OUT_DIR
set -u
out=${1:?OUT_DIR}; mkdir -p "$out"
for f in .gpu/debs/*.deb; do dpkg -x "$f" /; done; ldconfig
icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; [ -f $icd ] && export VK_DRIVER_FILES=$icd
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv > "$out/gpu.txt" 2>&1
cd .gpu
r() { echo "== $* $SCENE"; timeout 60 env "$@" ./render-split --size 1280x1024 --time 60 --out /tmp/x.png \
  $SCENE 2>&1 | grep -E "adapter|time:|mask"; }
{
for round in 1 2; do
  echo "## round $round"
  for m in ours pcss traditional; do
    SCENE="--scene assets/scenes/teapot.ron --method $m"
    r PENUMBRA_LAYER_WRITES=draw; r PENUMBRA_LAYER_WRITES=storage
  done
  SCENE="--scene assets/scenes/teapot.ron --method ours"
  # The cache is in `cs_main`, both axes' entry point where a draw writes the layer: against
  # PENUMBRA_LAYER_WRITES=draw above.
  r PENUMBRA_BLUR_CACHE=1 PENUMBRA_LAYER_WRITES=draw
  r PENUMBRA_DISTANCE_PCF=apart; r PENUMBRA_TILE_PIXELS=loop; r PULL_BACK=8
  SCENE="--scene assets/scenes/teapot.ron --method traditional"; r PENUMBRA_BLUR_CACHE=1 PENUMBRA_LAYER_WRITES=draw
  SCENE="--scene assets/scenes/teapot.ron --method hard"; r X=1
  for m in ours pcss hard; do SCENE="--scene assets/scenes/character.ron --method $m"; r X=1; done
  SCENE="--scene assets/scenes/room.ron --method ours"; r X=1
done
nvidia-smi --query-gpu=name,clocks.sm,clocks.max.sm --format=csv
} > "$out/diag.txt" 2>&1
head -c 6000 "$out/diag.txt"
DIAG
chmod +x .gpu/diag.sh
du -sh .gpu
