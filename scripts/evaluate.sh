#!/usr/bin/env bash
# Table-1 evaluation of the lane detector (METHOD.md section 6, generalised to sides scored on
# their own with a kind: tools/include/rgbd_lane_detector_tools/scoring.h).
#  1. generates the standard synthetic scenario set into build/data/ (skipped per sequence when
#     it already holds exactly these settings),
#  2. scores the modes paper, improved and their colour-only ablations on every sequence, and
#     checks the planes on the real KITTI frames against the LiDAR depth (../shared/realdata),
#     with the LiDAR depth and with depth from the colour stereo pair (StereoSGBM), which is
#     itself measured against the LiDAR (evaluate_stereo),
#  3. scores the improved mode's lane model (Result::lane_model) against the true lane model
#     (tools/include/rgbd_lane_detector_tools/lane_model_scoring.h) and the lane grid built from
#     it against the true boundaries (lane_grid_scoring.h), refits the confidence
#     calibration on these sequences (tools/scripts/fit_confidence.py) and checks the lane model
#     on held-out sequences of another seed (HELDOUT_SEED, HELDOUT_FRAMES),
#  4. writes the generated part of docs/RESULTS.md, the overlay pictures and score plots of
#     docs/images/.
# Run with the catkin workspace sourced (`make eval` builds and sources it).
# Environment: FRAMES (300), WIDTH (640), HEIGHT (380), SEED (1), DATA_DIR (build/data),
#   HELDOUT_SEED (2; empty: no held-out check), HELDOUT_FRAMES (200),
#   HELDOUT_DIR (build/data_seed$HELDOUT_SEED),
#   EVAL_DIR (build/eval), REALDATA (../shared/realdata), RESULTS (docs/RESULTS.md),
#   IMAGES (docs/images), TOOLS_BIN (folder of the tool executables, found automatically),
#   SOURCE_COMMIT (commit the tools were built from, default: this checkout's HEAD).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
FRAMES="${FRAMES:-300}"
WIDTH="${WIDTH:-640}"
HEIGHT="${HEIGHT:-380}"
SEED="${SEED:-1}"
HELDOUT_SEED="${HELDOUT_SEED-2}"
HELDOUT_FRAMES="${HELDOUT_FRAMES:-200}"
DATA_DIR="${DATA_DIR:-$ROOT/build/data}"
EVAL_DIR="${EVAL_DIR:-$ROOT/build/eval}"
EVAL_DIR_REL="$(realpath -m --relative-to="$ROOT" "$EVAL_DIR")"
REALDATA="${REALDATA:-$(cd "$ROOT/.." && pwd)/shared/realdata}"
RESULTS="${RESULTS:-$ROOT/docs/RESULTS.md}"
IMAGES="${IMAGES:-$ROOT/docs/images}"
PYTHON=/usr/bin/python3
HELDOUT_DIR="${HELDOUT_DIR:-$ROOT/build/data_seed$HELDOUT_SEED}"

# scenario:sensor pairs of the standard set: the highway set, then the real-street failures
# (kerb, tram rails, unpainted asphalt edge, intersections, crest and sag, yellow centre line),
# a lane change, a sharp bend (radius 90 m), and a night motorway under low beams with a bonnet in
# the bottom rows and a roof LiDAR's depth
SEQUENCES=(
  summer:clean cloudy:clean fog:clean overpass:clean solid:clean dashed:clean shadows:clean
  lane_like_objects:clean no_markings:clean curve:clean summer:kinect summer:sparse
  kerb:clean tram_rails:clean road_edge:clean intersection:clean crest_sag:clean
  yellow_centre:clean lane_change:clean sharp_bend:clean night_motorway:lidar
)

# shellcheck source=find_tool.sh
source "$(dirname "${BASH_SOURCE[0]}")/find_tool.sh"

GENERATE="$(find_tool generate_sequence)"
EVALUATE="$(find_tool evaluate_sequences)"
RUN="$(find_tool run_dataset)"
STEREO="$(find_tool evaluate_stereo)"
mkdir -p "$DATA_DIR" "$EVAL_DIR" "$IMAGES"

echo "== generating ${#SEQUENCES[@]} sequences of $FRAMES frames at ${WIDTH}x${HEIGHT} into $DATA_DIR"
start=$(date +%s)
args=()
for pair in "${SEQUENCES[@]}"; do
  scenario="${pair%%:*}"
  sensor="${pair##*:}"
  name="$scenario"
  [ "$sensor" != clean ] && name="${scenario}_${sensor}"
  "$GENERATE" --scenario "$scenario" --sensor "$sensor" --frames "$FRAMES" --width "$WIDTH" \
    --height "$HEIGHT" --seed "$SEED" --out "$DATA_DIR/$name" --skip-if-same
  args+=(--seq "$name=$DATA_DIR/$name")
done
# the held-out set: the same scenarios with another seed (the lane model's check)
heldout_args=()
if [ -n "$HELDOUT_SEED" ]; then
  echo "== generating the held-out set: seed $HELDOUT_SEED, $HELDOUT_FRAMES frames, into $HELDOUT_DIR"
  for pair in "${SEQUENCES[@]}"; do
    scenario="${pair%%:*}"
    sensor="${pair##*:}"
    name="$scenario"
    [ "$sensor" != clean ] && name="${scenario}_${sensor}"
    "$GENERATE" --scenario "$scenario" --sensor "$sensor" --frames "$HELDOUT_FRAMES" \
      --width "$WIDTH" --height "$HEIGHT" --seed "$HELDOUT_SEED" --out "$HELDOUT_DIR/$name" \
      --skip-if-same
    heldout_args+=(--seq "$name=$HELDOUT_DIR/$name")
  done
fi
gen_time=$(( $(date +%s) - start ))

args+=(--paper summer=01-SUMMER --paper fog=01-FOG --paper summer_sparse=R200)
if [ -d "$REALDATA/kitti2015" ]; then
  args+=(--kitti "kitti=$REALDATA/kitti2015" --kitti "kitti_sgbm=$REALDATA/kitti2015" --sgbm kitti_sgbm)
else
  echo "evaluate.sh: $REALDATA/kitti2015 not found, skipping the KITTI plane check" >&2
fi
if [ -d "$REALDATA/tum_office" ]; then
  args+=(--no-lane "tum_office=$REALDATA/tum_office")
fi
if [ -d "$REALDATA/kitti_stereo_negative" ]; then
  args+=(--no-lane "kitti_negative=$REALDATA/kitti_stereo_negative"
         --no-lane "kitti_negative_sgbm=$REALDATA/kitti_stereo_negative" --sgbm kitti_negative_sgbm)
fi

echo "== evaluating (modes paper, improved, paper-colour, improved-colour)"
start=$(date +%s)
"$EVALUATE" "${args[@]}" --out "$EVAL_DIR" --markdown "$EVAL_DIR/tables.md" \
  --csv "$EVAL_DIR/per_frame.csv" --images "$IMAGES" \
  --lane-model-markdown "$EVAL_DIR/lane_model.md" --lane-model-csv "$EVAL_DIR/lane_model.csv" \
  --lane-model-suffix " (seed $SEED)"
if [ -n "$HELDOUT_SEED" ]; then
  echo "== the lane model on the held-out set (seed $HELDOUT_SEED, improved mode)"
  mkdir -p "$EVAL_DIR/heldout"
  "$EVALUATE" "${heldout_args[@]}" --modes improved --out "$EVAL_DIR/heldout" \
    --images "$EVAL_DIR/heldout/images" --lane-model-markdown "$EVAL_DIR/heldout/lane_model.md" \
    --lane-model-csv "$EVAL_DIR/heldout/lane_model.csv" --lane-model-suffix " (held out: seed $HELDOUT_SEED)" \
    > "$EVAL_DIR/heldout/summary.txt"
fi
# the confidence calibration refitted on this run's boundaries (src/core/lane_model.cpp holds
# the table fitted at the commit that last changed the lane model)
"$PYTHON" "$ROOT/tools/scripts/fit_confidence.py" "$EVAL_DIR/lane_model.csv" > "$EVAL_DIR/confidence_fit.txt"
eval_time=$(( $(date +%s) - start ))
"$PYTHON" "$ROOT/tools/scripts/plot_scores.py" "$EVAL_DIR/per_frame.csv" "$IMAGES"

# KITTI overlays of both frames (improved mode) with the per-frame LiDAR plane check
if [ -d "$REALDATA/kitti2015" ]; then
  for mode in improved paper; do
    "$RUN" --dataset "$REALDATA/kitti2015" --mode "$mode" --out "$EVAL_DIR/kitti_$mode" \
      --plane-check --video none --quiet > "$EVAL_DIR/kitti_$mode.txt"
  done
  for f in "$EVAL_DIR"/kitti_improved/overlays/*.jpg; do
    cp "$f" "$IMAGES/kitti_$(basename "$f")"
  done
fi
# StereoSGBM depth against the LiDAR (one thread, so the ms column compares across runs)
for set in kitti2015 kitti_stereo_negative; do
  [ -d "$REALDATA/$set" ] && "$STEREO" --dataset "$REALDATA/$set" --threads 1 > "$EVAL_DIR/stereo_$set.md"
done

# The hand-labelled real frames (test/data/realdata_labels.yaml): each labelled ego boundary with
# its kind, the negatives, with the LiDAR depth and with StereoSGBM depth; overlays into $IMAGES
REAL="$(find_tool evaluate_real)"
if [ -d "$REALDATA" ]; then
  "$REAL" --labels "$ROOT/test/data/realdata_labels.yaml" --realdata "$REALDATA" --mode improved \
    --mode paper --markdown "$EVAL_DIR/real.md" --csv "$EVAL_DIR/real.csv" --images "$IMAGES" ||
    echo "evaluate.sh: evaluate_real found wrong sides (see $EVAL_DIR/real.md)" >&2
fi

# The real corpus (issue 26): the 23 street frames of six datasets and the RADIATE fog sequence,
# hand-labelled in test/data/realdata_streets.yaml and realdata_radiate_fog.yaml; the frames as
# recorded, with the LiDAR and with StereoSGBM where a right image exists; the sequence in order
# at its own rate with tracking and the lane model. Overlays stay in build/eval (the data is not
# ours to publish).
if [ -d "$REALDATA/streets" ] || [ -d "$REALDATA/sequences/radiate_fog" ]; then
  "$REAL" --labels "$ROOT/test/data/realdata_streets.yaml" \
    --labels "$ROOT/test/data/realdata_radiate_fog.yaml" --labels "$ROOT/test/data/realdata_labels.yaml" \
    --realdata "$REALDATA" --mode improved --mode paper --variant as_is \
    --markdown "$EVAL_DIR/real_corpus.md" --csv "$EVAL_DIR/real_corpus.csv" \
    --images "$EVAL_DIR/real_corpus_images" > /dev/null ||
    echo "evaluate.sh: evaluate_real found wrong sides on the real corpus (see $EVAL_DIR/real_corpus.md)" >&2
fi

# The street frames again in every stress variant (real_variants.h): the other side of the road
# (mirrored: left-hand traffic, kerbs on the left), no depth near the car, another camera (half
# the resolution), darker and brighter exposure, night. A proxy for roads and cameras nobody labelled:
# what is reported must stay on its line.
if [ -d "$REALDATA/streets" ]; then
  variant_args=()
  for v in mirrored no_near_depth half_resolution underexposed overexposed night; do
    variant_args+=(--variant "$v")
  done
  "$REAL" --labels "$ROOT/test/data/realdata_streets.yaml" --labels "$ROOT/test/data/realdata_labels.yaml" \
    --realdata "$REALDATA" --mode improved --depth dataset "${variant_args[@]}" \
    --markdown "$EVAL_DIR/real_corpus_variants.md" --csv "$EVAL_DIR/real_corpus_variants.csv" \
    > /dev/null || echo "evaluate.sh: evaluate_real found wrong sides in the stress variants (see $EVAL_DIR/real_corpus_variants.md)" >&2
fi

# SOURCE_COMMIT: commit the tools were built from, when that is not this checkout's HEAD
commit="${SOURCE_COMMIT:-$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)}"
dirty=""
if [ -z "${SOURCE_COMMIT:-}" ] && ! git -C "$ROOT" diff --quiet HEAD -- src include tools 2>/dev/null; then
  dirty=" (with uncommitted changes)"
fi
{
  echo "Generated by \`scripts/evaluate.sh\` at commit \`$commit\`$dirty: $FRAMES frames per"
  echo "sequence at ${WIDTH}x${HEIGHT}, seed $SEED (generation ${gen_time} s, cached sequences skipped;"
  echo "evaluation ${eval_time} s). Every sequence is scored with the same rules; ms/frame is the detector's own"
  echo "\`timings.total\` (single thread, the evaluator runs the four modes one after another)."
  echo
  cat "$EVAL_DIR/tables.md"
  echo "### Lane model tables (issue 14)"
  echo
  echo "What \`lane_model\` publishes (\`Result::lane_model\`, improved mode, in base_link through the"
  echo "fixed mount as the bag's /tf_static gives it) against the true lane model of each frame"
  echo "(\`tools/include/rgbd_lane_detector_tools/lane_model_scoring.h\`), on the sequences above"
  echo "(seed $SEED) and, held out, the same scenarios with seed ${HELDOUT_SEED:-(none)}."
  echo
  cat "$EVAL_DIR/lane_model.md"
  if [ -f "$EVAL_DIR/lane_grid.md" ]; then
    echo "### Lane grid table (issue 25)"
    echo
    echo "The \`lane_grid\` occupancy grid built from that lane model (\`LaneGrid\`, default size) against"
    echo "the true boundaries (\`tools/include/rgbd_lane_detector_tools/lane_grid_scoring.h\`), seed $SEED."
    echo
    cat "$EVAL_DIR/lane_grid.md"
  fi
  if [ -n "$HELDOUT_SEED" ] && [ -f "$EVAL_DIR/heldout/lane_model.md" ]; then
    echo "Held out: the same $((${#SEQUENCES[@]})) scenarios generated with seed $HELDOUT_SEED ($HELDOUT_FRAMES frames"
    echo "each), scored the same way; the confidence calibration was fitted on seed $SEED only."
    echo
    cat "$EVAL_DIR/heldout/lane_model.md"
  fi
  echo "The confidence calibration refitted on this run's seed-$SEED boundaries"
  echo "(\`tools/scripts/fit_confidence.py $EVAL_DIR_REL/lane_model.csv\`; \`calibratedConfidence()\` in"
  echo "\`src/core/lane_model.cpp\` holds the table of the run that last changed the lane model):"
  echo
  echo '```'
  cat "$EVAL_DIR/confidence_fit.txt"
  echo '```'
  echo
  if [ -f "$EVAL_DIR/kitti_improved.txt" ]; then
    echo "KITTI per-run summary (\`run_dataset --plane-check\`, road region below the horizon,"
    echo "central 30% of the columns, LiDAR depth <= 40 m):"
    echo
    for mode in improved paper; do
      echo "- $mode: $(grep -h 'plane check' "$EVAL_DIR/kitti_$mode.txt" || echo 'no plane reported')"
    done
    echo
  fi
  if [ -f "$EVAL_DIR/stereo_kitti2015.md" ]; then
    echo "StereoSGBM depth against the LiDAR (\`evaluate_stereo --threads 1\`, the matcher of"
    echo "\`--depth sgbm\`; kitti2015 tuned on, kitti_stereo_negative held out):"
    echo
    for set in kitti2015 kitti_stereo_negative; do
      [ -f "$EVAL_DIR/stereo_$set.md" ] && { echo "$set: $(head -n 1 "$EVAL_DIR/stereo_$set.md")"; echo; tail -n +3 "$EVAL_DIR/stereo_$set.md"; echo; }
    done
  fi
  if [ -f "$EVAL_DIR/real.md" ]; then
    echo "### Hand-labelled real frames"
    echo
    echo "\`evaluate_real\` on the frames of \`../shared/realdata\` labelled in"
    echo "\`test/data/realdata_labels.yaml\` (each ego boundary an image polyline with its kind). A reported"
    echo "side is right when at least 80% of its points lie within 0.30 m (laterally, on the LiDAR road"
    echo "plane) of the labelled line of the same kind; any side reported on a frame without a lane is"
    echo "wrong. The last column compares the reported plane with a RANSAC plane of the LiDAR road points."
    echo
    cat "$EVAL_DIR/real.md"
    echo
    echo "Overlays (improved mode; the labelled lines in thin white):"
    echo
    for f in "$IMAGES"/real_*_improved.jpg; do
      [ -f "$f" ] && echo "- \`$(basename "$f" .jpg)\`: ![$(basename "$f" .jpg)](images/$(basename "$f"))"
    done
    echo
  fi
  if [ -f "$EVAL_DIR/real_corpus.md" ]; then
    echo "### The real corpus (issue 26)"
    echo
    echo "\`evaluate_real\` on every frame of \`../shared/realdata/streets\` (23 frames, six datasets,"
    echo "four countries), the KITTI frames and negatives above, and the 50 frames of"
    echo "\`sequences/radiate_fog\` (fog, drops on the lens, 15 Hz), hand-labelled in"
    echo "\`test/data/realdata_streets.yaml\` and \`realdata_radiate_fog.yaml\` (key frames, interpolated"
    echo "per row). Frames as recorded; each street frame on its own (detector reset), the sequence in"
    echo "order at its camera stamps with tracking and the lane model, the camera mount given as the"
    echo "vehicle frame (the median LiDAR road plane of the sequence). Same rule as above (80% of a"
    echo "side's points within 0.30 m of its labelled line, the labelled kind); solid/dashed and colour"
    echo "are scored on the sides reported right; the plane against the LiDAR's (calib.yaml's road"
    echo "plane for the street frames); the lane model's ego boundaries scored like sides, and the"
    echo "frame-to-frame change of their c0. Overlays: \`$EVAL_DIR_REL/real_corpus_images\`."
    echo
    cat "$EVAL_DIR/real_corpus.md"
    echo
  fi
  if [ -f "$EVAL_DIR/real_corpus_variants.md" ]; then
    echo "### The real corpus in stress variants"
    echo
    echo "The same street and KITTI frames (LiDAR depth, improved mode, each frame on its own),"
    echo "changed as other roads and cameras would change them (\`tools/include/rgbd_lane_detector_tools/dataset/real_variants.h\`):"
    echo "mirrored left-right (left-hand traffic: kerbs and centre lines on the other side), no depth"
    echo "in the bottom 30% of the rows, half the resolution, colour at 60% and at 140%, and night (each"
    echo "row from 45% at the bottom to 8% at the horizon, as low beams light the road, and noise). The labels"
    echo "change with the frame. A proxy for what nobody has labelled: the \`wrong\` column is what a"
    echo "user would see. Per-frame verdicts: \`$EVAL_DIR_REL/real_corpus_variants.md\`."
    echo
    sed '/^$/q' "$EVAL_DIR/real_corpus_variants.md" | grep -v '| sensor |'
    echo
  fi
  echo "Pictures (paper mode left, improved right, middle frame of each sequence):"
  echo
  for pair in "${SEQUENCES[@]}"; do
    scenario="${pair%%:*}"
    sensor="${pair##*:}"
    name="$scenario"
    [ "$sensor" != clean ] && name="${scenario}_${sensor}"
    echo "- \`$name\`: ![$name](images/$name.jpg) [per-frame scores](images/scores_$name.png)"
  done
  [ -f "$IMAGES/kitti.jpg" ] && echo "- KITTI 000001_10, paper | improved: ![kitti](images/kitti.jpg)"
  [ -f "$IMAGES/kitti_sgbm.jpg" ] && echo "- KITTI 000001_10 with SGBM depth, paper | improved: ![kitti_sgbm](images/kitti_sgbm.jpg)"
  for name in kitti_negative kitti_negative_sgbm; do
    [ -f "$IMAGES/$name.jpg" ] && echo "- KITTI stereo negative (no lane)$([ "$name" = kitti_negative_sgbm ] && echo ' with SGBM depth'), paper | improved: ![$name](images/$name.jpg)"
  done
  for f in "$IMAGES"/kitti_[0-9]*.jpg; do
    [ -f "$f" ] && echo "- KITTI $(basename "$f" .jpg | sed 's/^kitti_//') (improved): ![kitti](images/$(basename "$f"))"
  done
  [ -f "$IMAGES/tum_office.jpg" ] && echo "- TUM office (no road): ![tum_office](images/tum_office.jpg)"
  echo
  echo "![summary](images/summary.png)"
} > "$EVAL_DIR/generated.md"
"$PYTHON" "$ROOT/tools/scripts/update_results.py" "$EVAL_DIR/generated.md" "$RESULTS"
echo "== wrote $RESULTS and $IMAGES (per-frame CSV: $EVAL_DIR/per_frame.csv)"
