#!/usr/bin/env python3
"""Per-stage CPU breakdown of a lockstep simulation run from a perf call-graph profile.

    perf record --call-graph dwarf,16384 -F 149 -o run.perf.data labodrone-bench sim inspect --vision real --seed 1
    perf script -i run.perf.data -F period,ip,sym | scripts/profile_stages.py --cpu-s CPU --frames N

Each sample goes to the stage of the innermost frame on its stack that names one (the rules below,
checked from the leaf towards main); samples whose stack names none are "other". With the process's
CPU time (--cpu-s, e.g. user + sys from /usr/bin/time) and the number of simulated video frames
(--frames: simulated seconds x fps) it prints ms of CPU per simulated frame beside the share.
docs/sim.md ("Where the time of a real-vision run goes") shows its output.
"""
import argparse
import collections
import sys

# (stage, substring of a demangled frame). Order matters only between rules that can match the same
# frame; the innermost matching frame wins, so a SIFT call inside the bottom camera's platform
# detection counts as SIFT, and the camera is told apart by a second pass (CAMERA_RULES).
STAGE_RULES = [
    ("render", "LabRenderer::render"),
    ("H.264 encode/decode", "H264Encoder::"),
    ("H.264 encode/decode", "H264Decoder::"),
    ("SLAM mapping (keyframes, BA)", "slam::LocalMapper::"),
    ("SLAM mapping (keyframes, BA)", "slam::LoopCloser::"),
    ("SLAM relocalization", "slam::Relocalizer::"),
    ("SLAM features (FAST, pyramid)", "slam::FeatureExtractor::"),
    ("SLAM features (FAST, pyramid)", "slam::small_blurry_image"),
    ("SLAM tracking (other)", "slam::SlamSystem::"),
    ("planar SIFT detection", "SiftDetector::detect"),
    ("planar template detection", "TemplateMatchDetector::detect"),
    ("planar tracking and pose", "PlanarObjectLocalizer::"),
    ("face", "FaceFrontEnd::"),
    ("face", "face::"),
    ("grey conversion", "LabPipelines::grey_of"),
    ("estimator", "StateEstimator::"),
    ("estimator", "DroneEkf::"),
    ("estimator", "FilterCore::"),
    ("control (FlightStack tick)", "FlightStack::Impl::tick"),
    ("physics and sensors", "SimulatedLab::step"),
    ("setup (loading, template features)", "make_flight"),
    ("setup (loading, template features)", "make_experiment"),
    ("setup (loading, template features)", "_dl_"),
]
CAMERA_RULES = [("bottom", "LabPipelines::run_bottom_camera"), ("front", "LabPipelines::run_front_camera")]
KERNEL_MARK = "asm_exc_page_fault"


def classify(frames):
    stage = next((s for f in frames for s, key in STAGE_RULES if key in f), "other (link, bookkeeping, libc)")
    camera = next((c for f in frames for c, key in CAMERA_RULES if key in f), "")
    faulting = any(KERNEL_MARK in f for f in frames)
    return stage, camera, faulting


def samples(stream):
    period, frames = None, []
    for line in stream:
        if not line.strip():
            if period is not None:
                yield period, frames
            period, frames = None, []
        elif not line.startswith("\t"):
            period = int(line.split()[-1])
        else:
            parts = line.strip().split(None, 1)
            frames.append(parts[1] if len(parts) > 1 else parts[0])
    if period is not None:
        yield period, frames


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cpu-s", type=float, help="the run's CPU time (user + sys), seconds")
    ap.add_argument("--frames", type=float, help="simulated video frames (simulated seconds x fps)")
    a = ap.parse_args()
    by_stage = collections.Counter()
    by_camera = collections.Counter()
    faults = 0
    total = 0
    for period, frames in samples(sys.stdin):
        stage, camera, faulting = classify(frames)
        by_stage[stage] += period
        if camera:
            by_camera[(camera, stage)] += period
        faults += period if faulting else 0
        total += period
    if total == 0:
        sys.exit("no samples on stdin (perf script -F period,ip,sym output expected)")

    def row(name, v):
        share = 100.0 * v / total
        ms = f"{1000.0 * a.cpu_s * v / total / a.frames:8.2f} ms/frame" if a.cpu_s and a.frames else ""
        print(f"  {name:<44} {share:6.1f} %  {ms}")

    print("stage (innermost frame wins)")
    for stage, v in by_stage.most_common():
        row(stage, v)
    print("vision by camera")
    for (camera, stage), v in sorted(by_camera.items(), key=lambda kv: -kv[1]):
        row(f"{camera}: {stage}", v)
    print("of all the above, in page faults (kernel)")
    row("page faults", faults)


if __name__ == "__main__":
    main()
