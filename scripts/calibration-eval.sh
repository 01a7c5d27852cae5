#!/usr/bin/env bash
# Issue #19 part 4: the Metamoran accuracy on cascade scenes from a perfect board, from an
# imperfect board (seeded channel errors: phase ±180°, gain ±3 dB, delay ±0.5 bin) as
# recorded, and from the same board calibrated on its own corner-reflector capture.
#   scripts/calibration-eval.sh [BOARD] [SEED] [COUNT] [OUT] [RADAR]
# Prints three eval reports (release binary) and the calibration's coherence summary.
set -euo pipefail
board=${1:-5} seed=${2:-9701} count=${3:-30} out=${4:-target/calibration-eval} radar=${5:-cascade}
bin=target/release/metamoran
cargo build -q --release --bin metamoran
rm -rf "$out"; mkdir -p "$out"/{perfect,raw,calibrated,corner}
$bin simulate --preset corner --radar "$radar" --board "$board" --seed 1 --out "$out/corner" 2>/dev/null
$bin calibrate "$out/corner/corner-board$board-1-0000" --out "$out/board$board.toml"
# A second corner capture of the same board (other noise, other reflector phase): the held-out
# coherence.
$bin simulate --preset corner --radar "$radar" --board "$board" --seed 2 --out "$out/corner" 2>/dev/null
$bin calibrate "$out/corner/corner-board$board-2-0000" --check "$out/board$board.toml"
$bin simulate --preset parking-lot --radar "$radar" --seed "$seed" --count "$count" --out "$out/perfect" 2>/dev/null
$bin simulate --preset parking-lot --radar "$radar" --board "$board" --seed "$seed" --count "$count" --out "$out/raw" 2>/dev/null
cp -r "$out"/raw/. "$out/calibrated/"
for d in "$out"/calibrated/*/; do
  cp "$out/board$board.toml" "$d/calibration.toml"
  sed -i 's/^adc_layout\( *\)= \(.*\)$/adc_layout\1= \2\ncalibration_file = "calibration.toml"/' "$d/scene.toml"
done
for set in perfect raw calibrated; do
  echo "== $set"
  $bin eval "$out/$set" --modes naive,metamoran
done
