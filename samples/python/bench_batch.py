#!/usr/bin/env python3
"""Images per second for a batch of same-size photos with random poses: binding per image
against one binding shared by the batch (Deformer.deform(pose, image=...) one at a time, and
Deformer.deform_many for the whole batch).

    PYTHONPATH=build/python /usr/bin/python3 samples/python/bench_batch.py [--size 512] [--count 32]

The photos are the sample photos (samples/data) resized to SIZE x SIZE, cycled to COUNT images;
one multicage is proposed on the first and used for all (a dataset of one framing); poses are
multicage.random_pose(cage, AMPLITUDE, seed=k), drawn before timing (their cost is printed too).
Each way keeps its COUNT outputs (as a data loader building a batch does).
CPU backend; OpenCV's thread count is cv2.getNumThreads() (every core unless --threads).
"""

import argparse
import os
import platform
import statistics
import sys
import time

from sample_imports import cv2
from sample_imports import multicage as mc

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data")


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def best_of(repeats, run):
    """Median seconds of `repeats` runs of run()."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        run()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--size", type=int, default=512, help="photos are SIZE x SIZE (default: %(default)s)")
    p.add_argument("--count", type=int, default=32, help="images per batch (default: %(default)s)")
    p.add_argument("--grid-steps", default="1,4", help="grid steps to measure (default: %(default)s)")
    p.add_argument("--amplitude", type=float, default=12, help="random pose amplitude, px (default: %(default)s)")
    p.add_argument("--repeats", type=int, default=3, help="runs per figure, the median is shown (default: %(default)s)")
    p.add_argument("--threads", type=int, default=None, help="cv2.setNumThreads (default: all cores)")
    args = p.parse_args(argv)
    if args.threads is not None:
        cv2.setNumThreads(args.threads)
    names = sorted(n for n in os.listdir(DATA) if n.lower().endswith((".jpg", ".png")))
    photos = [cv2.resize(mc.imread(os.path.join(DATA, n), cv2.IMREAD_COLOR), (args.size, args.size), interpolation=cv2.INTER_AREA)
              for n in names]
    images = [photos[k % len(photos)] for k in range(args.count)]
    cage = mc.propose_multicage(images[0])
    t0 = time.perf_counter()
    poses = [mc.random_pose(cage, args.amplitude, seed=k) for k in range(args.count)]
    pose_ms = (time.perf_counter() - t0) * 1e3 / args.count
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"{cpu_model()}, {os.cpu_count()} cores, OpenCV threads {cv2.getNumThreads()}, load average "
          f"{load:.2f}; {args.count} photos {args.size}x{args.size}, {cage.polygon_count} polygons, "
          f"{cage.vertex_count} vertices, CPU backend; random_pose {pose_ms:.2f} ms each")
    print(f"{'grid step':>9} | {'bind per image':>15} | {'one binding, deform(image=)':>27} | "
          f"{'one binding, deform_many':>24} | speed-up")
    for step in (int(s) for s in args.grid_steps.split(",")):
        # Each way keeps its outputs, as a data loader building a batch does.
        def per_image():
            return [mc.Deformer(image, cage, backend="cpu", grid_step=step).deform(pose)
                    for image, pose in zip(images, poses)]

        deformer = mc.Deformer(images[0], cage, backend="cpu", grid_step=step)

        def one_by_one():
            return [deformer.deform(pose, image=image) for image, pose in zip(images, poses)]

        def batch():
            return deformer.deform_many(poses, images)

        rates = [args.count / best_of(args.repeats, run) for run in (per_image, one_by_one, batch)]
        print(f"{step:>9} | {rates[0]:>9.1f} img/s | {rates[1]:>21.1f} img/s | {rates[2]:>18.1f} img/s | "
              f"{rates[2] / rates[0]:.1f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
