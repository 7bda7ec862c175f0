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

--augment: instead, multicage.MulticageWarp as a training loop calls it (one image, a mask
and 8 boxes per call, a new random pose each, one thread) against a plain cv2.remap of the
same image and the elastic recipe (Simard et al. 2003: uniform noise fields smoothed by a
Gaussian, sigma 4, alpha 34, then cv2.remap), timed in turn, round after round, in one run:
rates and ratios (a machine's load hits all of them alike).
"""

import argparse
import os
import platform
import statistics
import sys
import time

from sample_imports import cv2, np
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


def elastic(image, rng, grid_x, grid_y, alpha=34.0, sigma=4.0):
    """The usual elastic recipe: a smoothed uniform random field per axis, then remap."""
    h, w = image.shape[:2]
    dx = cv2.GaussianBlur(rng.uniform(-1, 1, (h, w)).astype(np.float32), (0, 0), sigma)
    dy = cv2.GaussianBlur(rng.uniform(-1, 1, (h, w)).astype(np.float32), (0, 0), sigma)
    return cv2.remap(image, grid_x + alpha * dx, grid_y + alpha * dy, cv2.INTER_LINEAR,
                     borderMode=cv2.BORDER_REFLECT_101)


def augment_rates(args, images):
    """MulticageWarp against cv2.remap and the elastic recipe, interleaved: per grid step,
    medians over rounds of COUNT images each."""
    cv2.setNumThreads(1)
    size = args.size
    image = images[0]
    mask = (mc.propose_segmentation(image) > 0).astype(np.uint8)
    boxes = [(40 + 50 * k, 60, 100 + 50 * k, 200) for k in range(8)]
    grid_x, grid_y = np.meshgrid(np.arange(size, dtype=np.float32), np.arange(size, dtype=np.float32))
    rng = np.random.default_rng(0)
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"{cpu_model()}, OpenCV threads 1, load average {load:.2f}; {size}x{size}, amplitude "
          f"{args.amplitude:g} px, medians of {args.repeats} interleaved rounds of {args.count} images")
    print(f"map step: {'the grid step' if args.map_step is None else args.map_step}")
    print(f"{'grid step':>9} | {'MulticageWarp image':>19} | {'+ mask + 8 boxes':>16} | {'cv2.remap':>10} | "
          f"{'ratio':>6} | {'elastic':>8} | ratio")
    for step in (int(s) for s in args.grid_steps.split(",")):
        warp = mc.MulticageWarp(amplitude=args.amplitude, grid_step=step, map_step=args.map_step, seed=0)
        warp(image=image, name="photo", index=0)  # proposes and binds once, as a loader's first batch
        mx, my = mc.Deformer(image, warp._cage_for(image, "photo")[1], backend="cpu",
                             grid_step=step).compute_maps(mc.random_pose(warp._cage_for(image, "photo")[1], 8, seed=1))
        counter = [0]

        def run_warp():
            for _ in range(args.count):
                counter[0] += 1
                warp(image=image, name="photo", index=counter[0])

        def run_full():
            for _ in range(args.count):
                counter[0] += 1
                warp(image=image, mask=mask, bboxes=boxes, name="photo", index=counter[0])

        def run_remap():
            for _ in range(args.count):
                cv2.remap(image, mx, my, cv2.INTER_LINEAR)

        def run_elastic():
            for _ in range(args.count):
                elastic(image, rng, grid_x, grid_y)

        runs = (run_warp, run_full, run_remap, run_elastic)
        times = [[] for _ in runs]
        for _ in range(args.repeats):
            for k, run in enumerate(runs):
                t0 = time.perf_counter()
                run()
                times[k].append(time.perf_counter() - t0)
        rates = [args.count / statistics.median(t) for t in times]
        print(f"{step:>9} | {rates[0]:>12.1f} img/s | {rates[1]:>10.1f} img/s | {rates[2]:>4.0f} img/s | "
              f"{rates[2] / rates[0]:>5.2f}x | {rates[3]:>4.0f}/s | {rates[3] / rates[0]:.2f}x")
    print("ratio: MulticageWarp's time per image (image only) over cv2.remap's, and over the elastic recipe's")
    return 0


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--size", type=int, default=512, help="photos are SIZE x SIZE (default: %(default)s)")
    p.add_argument("--count", type=int, default=32, help="images per batch (default: %(default)s)")
    p.add_argument("--grid-steps", default="1,4", help="grid steps to measure (default: %(default)s)")
    p.add_argument("--amplitude", type=float, default=12, help="random pose amplitude, px (default: %(default)s)")
    p.add_argument("--repeats", type=int, default=3, help="runs per figure, the median is shown (default: %(default)s)")
    p.add_argument("--threads", type=int, default=None, help="cv2.setNumThreads (default: all cores)")
    p.add_argument("--map-step", type=int, default=None,
                   help="--augment: MulticageWarp's map_step (default: the grid step; 1: every pixel)")
    p.add_argument("--augment", action="store_true",
                   help="MulticageWarp (one thread) against cv2.remap and the elastic recipe instead")
    args = p.parse_args(argv)
    if args.threads is not None:
        cv2.setNumThreads(args.threads)
    names = sorted(n for n in os.listdir(DATA) if n.lower().endswith((".jpg", ".png")))
    photos = [cv2.resize(mc.imread(os.path.join(DATA, n), cv2.IMREAD_COLOR), (args.size, args.size), interpolation=cv2.INTER_AREA)
              for n in names]
    images = [photos[k % len(photos)] for k in range(args.count)]
    if args.augment:
        return augment_rates(args, images)
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
