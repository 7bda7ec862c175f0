#!/usr/bin/env python3
"""Data augmentation with multicage deformation.

Proposes a multicage around the objects of an image (or of its mask), then writes COUNT
randomly deformed copies of the image and of its mask. Every vertex moves at most BOUND
pixels; poses come from multicage.random_pose: each polygon gets its own small rotation,
scale, shift and jitter, and poses that would make polygons cross or fold the image over are
drawn again. The mask is deformed with the same inverse maps as the image (nearest
neighbour), so labels stay aligned with pixels.

Outputs in OUT: NAME_000.png, NAME_000_mask.png, ..., and NAME_cage.yml holding the cage and
every pose used (open it with `multicage deform IMAGE NAME_cage.yml --pose aug001`).

From a build tree:  PYTHONPATH=build/python python3 samples/python/augment.py IMAGE
After install:      python3 <prefix>/share/multicage/samples/python/augment.py IMAGE
"""

import argparse
import os
import sys

from sample_imports import cv2, multicage, np


def parse_args(argv):
    p = argparse.ArgumentParser(
        description="Propose a multicage for IMAGE and write randomly deformed copies of the "
                    "image and its mask (data augmentation).")
    p.add_argument("image", help="input image (8/16-bit or float; gray, BGR or BGRA)")
    p.add_argument("--mask", help="mask or label image of the same size (default: the "
                                  "proposal's own segmentation); the cage is proposed from it")
    p.add_argument("-o", "--output", default="augmented", help="output folder (default: %(default)s)")
    p.add_argument("-n", "--count", type=int, default=8, help="number of copies (default: %(default)s)")
    p.add_argument("--bound", type=float, default=12.0,
                   help="largest vertex displacement in pixels (default: %(default)s)")
    p.add_argument("--seed", type=int, default=None, help="random seed, for repeatable output")
    p.add_argument("--grid-step", type=int, default=2, help="a mesh node every N pixels (default: %(default)s)")
    p.add_argument("--backend", choices=["auto", "cpu", "gpu"], default="auto",
                   help="where to deform (default: %(default)s)")
    p.add_argument("--method", default=None,
                   help="proposal method: auto, threshold, adaptive, grabcut, saliency, spectral "
                        "(default: auto; 'mask' or 'labels' with --mask)")
    p.add_argument("--max-vertices", type=int, default=48, help="cage vertex budget (default: %(default)s)")
    args = p.parse_args(argv)
    if args.count < 1:
        p.error("--count must be at least 1")
    if args.bound <= 0:
        p.error("--bound must be positive")
    return args


def read_image(path, what):
    if not os.path.isfile(path):
        sys.exit(f"augment.py: {what} {path}: no such file")
    try:
        return multicage.imread(path)  # as the CLI reads: a truncated file is refused
    except multicage.Error as e:
        sys.exit(f"augment.py: {what} {e}")


def fill_uncovered(mapx, mapy):
    """Pixels no deformed triangle covers (a fraction of a pixel at the image border) keep
    their own position, instead of the border value."""
    uncovered = mapx < -1000.0
    ys, xs = np.nonzero(uncovered)
    mapx[uncovered] = xs
    mapy[uncovered] = ys
    return int(uncovered.sum())


def main(argv=None):
    args = parse_args(argv)
    image = read_image(args.image, "image")
    if args.mask:
        mask = read_image(args.mask, "mask")
        if mask.shape[:2] != image.shape[:2]:
            sys.exit(f"augment.py: mask {args.mask} is {mask.shape[1]}x{mask.shape[0]} but the image "
                     f"is {image.shape[1]}x{image.shape[0]}")
        if mask.ndim == 3:
            mask = cv2.cvtColor(mask, cv2.COLOR_BGR2GRAY if mask.shape[2] == 3 else cv2.COLOR_BGRA2GRAY)
        method = args.method or ("mask" if len(np.unique(mask)) <= 2 else "labels")
        source = mask
    else:
        method = args.method or "auto"
        mask = None
        source = image
    try:
        cage = multicage.propose_multicage(source, method=method, max_vertices=args.max_vertices)
        if mask is None:
            mask = multicage.propose_segmentation(image, method=method)
    except multicage.NoObjectFoundError:
        sys.exit("augment.py: no object found in the image; nothing to deform (try --method or --mask)")
    except multicage.Error as e:
        sys.exit(f"augment.py: cannot propose a multicage: {e}")

    deformer = multicage.Deformer(image, cage, grid_step=args.grid_step, backend=args.backend)
    os.makedirs(args.output, exist_ok=True)
    stem = os.path.splitext(os.path.basename(args.image))[0]
    written = 0
    for k in range(args.count):
        # The library's random poses: smooth, every polygon simple, nested and disjoint as at
        # rest, no fold-over on this deformer's mesh; copy k of --seed S has its own seed.
        seed = None if args.seed is None else int(np.random.SeedSequence([args.seed, k]).generate_state(1, np.uint64)[0])
        pose = multicage.random_pose(cage, args.bound, seed=seed, deformer=deformer)
        # One set of inverse maps for both: bilinear for the image, nearest neighbour for the
        # mask (labels are never blended), so every mask pixel stays on its image pixel.
        mapx, mapy = deformer.compute_maps(pose)
        fill_uncovered(mapx, mapy)
        image_out = cv2.remap(image, mapx, mapy, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
        mask_out = cv2.remap(mask, mapx, mapy, cv2.INTER_NEAREST, borderMode=cv2.BORDER_REPLICATE)
        base = os.path.join(args.output, f"{stem}_{k:03d}")
        if not (cv2.imwrite(base + ".png", image_out) and cv2.imwrite(base + "_mask.png", mask_out)):
            sys.exit(f"augment.py: cannot write {base}.png")
        cage.add_pose(f"aug{k:03d}", pose)
        written += 1
    cage.save(os.path.join(args.output, f"{stem}_cage.yml"))
    print(f"wrote {written} images and masks to {args.output} ({cage.polygon_count} polygons, "
          f"{cage.vertex_count} vertices, {deformer.backend}, bound {args.bound:g} px)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
