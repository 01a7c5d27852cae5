#!/usr/bin/env python3
"""How far the trust test's threshold can move detection, per radar, from `eval --samples` files.

    python3 scripts/trust-ceiling.py ev/*.json

For each radar (file names holding `xwr18xx` or `cascade`) it prints how many objects have any
module candidate within 1 m of the truth (what a perfect chooser could reach), how many the trust
test's chosen depth is within 1 m for (`judged_error_m`: detected or not), and for a sweep of
detection thresholds on the reported confidence (the margin rule of trust.rs kept, its log-odds
recomputed by calibrate-trust.py's copy of the choice) the share detected, the share of
detections over 1 m and the share of objects confidently wrong (detected and over 3 m). The
confidences are the binary's own; at trust.rs's threshold (0.8) the detected set is the one
`eval` reports (checked). numpy (through calibrate-trust.py).
"""
import importlib.util
import json
import os
import sys

_spec = importlib.util.spec_from_file_location(
    "calibrate_trust", os.path.join(os.path.dirname(os.path.abspath(__file__)), "calibrate-trust.py")
)
ct = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(ct)
# The score's constants of trust.rs (RADAR_NATS_PER_DB, DOPPLER_NATS, SIDE_LOBE_NATS).
SCORE = (0.15, 4.0, 2.0)

MIN_LOG_ODDS = 0.5
THRESHOLDS = [0.5, 0.6, 0.7, 0.8, 0.85, 0.9]


def radar(path):
    name = os.path.basename(path)
    return "xwr18xx" if "xwr18xx" in name else "cascade" if "cascade" in name else "other"


def main(paths):
    groups = {}
    for path in paths:
        for s in json.load(open(path)):
            groups.setdefault(radar(path), []).append(s)
    for name, samples in sorted(groups.items()):
        n = len(samples)
        present = sum(
            1
            for s in samples
            if s.get("evidence")
            and any(abs(c["depth_m"] - s["truth_m"]) <= 1.0 for c in s["evidence"]["candidates"])
        )
        chosen = sum(
            1
            for s in samples
            if s.get("judged_error_m") is not None and abs(s["judged_error_m"]) <= 1.0
        )
        print(f"{name}: {n} objects; a candidate within 1 m {100 * present / n:.1f} %, "
              f"the chosen depth within 1 m {100 * chosen / n:.1f} %")
        at_08 = {id(s) for s in detected(samples, 0.8)}
        reported = {id(s) for s in samples if s.get("error_m") is not None}
        if at_08 != reported:
            print(f"  (at 0.8 this differs from eval's detections on {len(at_08 ^ reported)} objects)")
        print("  threshold  detected  > 1 m (of detected)  confidently wrong")
        for t in THRESHOLDS:
            det = detected(samples, t)
            over1 = sum(abs(s["judged_error_m"]) > 1.0 for s in det)
            wrong = sum(abs(s["judged_error_m"]) > 3.0 for s in det)
            print(f"  {t:9.2f}  {100 * len(det) / n:7.1f} %  {100 * over1 / max(len(det), 1):18.1f} %"
                  f"  {100 * wrong / n:16.1f} %")


def detected(samples, threshold):
    """The samples a threshold on the confidence would report as detected."""
    return [
        s
        for s in samples
        if s.get("confidence") is not None
        and s.get("judged_error_m") is not None
        and s["confidence"] >= threshold
        and margin(s) >= MIN_LOG_ODDS
    ]


def margin(sample):
    """The chosen candidate's log-odds against the other candidates (trust.rs `margin`)."""
    judged = ct.judge(sample["evidence"], *SCORE) if sample.get("evidence") else None
    return judged[1][1] if judged else float("-inf")


if __name__ == "__main__":
    main(sys.argv[1:])
