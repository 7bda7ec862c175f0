#!/usr/bin/env python3
"""Data augmentation at scale with Dask: every image of a folder, on a local cluster or a real one.

For each image of IMAGES_DIR (a task of its own): a multicage (proposed from the image, or
--cage scaled to it), and COPIES calls of one multicage.MulticageWarp on it (each seeded by
--seed, the image's name and the copy number, so any machine draws the same): the deformed
image, its deformed mask and its moved annotations, written to OUT_DIR:

    NAME_000.png        the image deformed to pose 0 (16-bit images stay 16-bit; float: .tiff)
    NAME_000_mask.png   the mask deformed with the same maps (nearest neighbour: labels stay labels)
    NAME_000.json       the pose, its seed, and the annotations moved with the image
    ...
    NAME_cage.yml       the multicage and every pose (multicage deform NAME.jpg NAME_cage.yml --pose aug000)

Masks: IMAGES_DIR/NAME_mask.png when it exists (any label image), else the proposal's own
segmentation. Annotations: IMAGES_DIR/NAME.json when it exists, {"keypoints": [[x, y], ...],
"boxes": [[x0, y0, x1, y1], ...]} in pixels; keypoints move with the image
(Deformer.transform_points; "keypoints_visible" says which landed inside the output) and each
box becomes the bounds of its moved outline (MulticageWarp: a bent edge stays inside its box).

Images are read as the CLI reads them (multicage.imread): a damaged file (a truncated JPEG or
PNG, an empty file, a file that is not an image) gets no output and is named in the summary;
the other images still finish, and the exit status is 1.

Every file is written atomically (a temporary file in OUT_DIR, then a rename), so an interrupted
run leaves whole files only; a rerun skips every copy whose three files exist and an image
whose copies and cage file all exist. The outputs do not depend on where or in what order
the tasks run: a cluster run gives the same bytes as --scheduler synchronous.

    # a local cluster, one worker process per core (the default)
    PYTHONPATH=build/python /usr/bin/python3 samples/python/dask_augment.py samples/data -o /tmp/augmented
    # one process, no cluster (for debugging, and the reference the test compares with)
    ... --scheduler synchronous
    # a real cluster: `dask-scheduler` on one machine, `dask-worker tcp://HOST:8786` on each
    # (with multicage importable there, and OUT_DIR on storage every worker can write)
    ... --scheduler tcp://HOST:8786
"""

import argparse
import hashlib
import json
import os
import sys
import tempfile

from sample_imports import cv2, np
from sample_imports import multicage as mc

IMAGE_EXTENSIONS = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".webp")


def parse_args(argv):
    p = argparse.ArgumentParser(
        description="Randomly deformed copies of every image of a folder, with their masks and "
                    "annotations, computed by Dask on a local cluster or a real one.")
    p.add_argument("images", metavar="IMAGES_DIR", help="folder of images (NAME_mask.png and NAME.json "
                                                        "beside an image are its mask and annotations)")
    p.add_argument("-o", "--output", metavar="OUT_DIR", required=True, help="output folder")
    p.add_argument("--cage", help="a cage file (YAML or JSON) for every image, scaled to each "
                                  "(default: a multicage proposed from each image)")
    p.add_argument("--copies", type=int, default=4, help="deformed copies per image (default: %(default)s)")
    p.add_argument("--seed", type=int, default=0, help="seed of every random pose (default: %(default)s)")
    p.add_argument("--amplitude", type=float, default=None,
                   help="largest vertex displacement in pixels (default: 2.5%% of the image's longer side)")
    p.add_argument("--grid-step", type=int, default=2, help="a mesh node every N pixels (default: %(default)s)")
    p.add_argument("--scheduler", metavar="ADDRESS", default=None,
                   help="a Dask scheduler (tcp://HOST:8786); 'synchronous': this process only, no "
                        "cluster; default: a local cluster")
    p.add_argument("--workers", type=int, default=None,
                   help="worker processes of the local cluster (default: one per core)")
    p.add_argument("--cv-threads", type=int, default=None,
                   help="OpenCV threads inside each task (default: 1 on a cluster, where the workers "
                        "share the cores; all cores with --scheduler synchronous)")
    args = p.parse_args(argv)
    if args.copies < 1:
        p.error("--copies must be at least 1")
    if args.amplitude is not None and not args.amplitude >= 0:
        p.error("--amplitude must be >= 0")
    if args.grid_step < 1:
        p.error("--grid-step must be at least 1")
    if args.workers is not None and args.workers < 1:
        p.error("--workers must be at least 1")
    if not os.path.isdir(args.images):
        p.error(f"{args.images}: no such folder")
    if args.cage and not os.path.isfile(args.cage):
        p.error(f"--cage {args.cage}: no such file")
    return args


def list_images(folder):
    """The images of folder, sorted: image files that are not a NAME_mask.png."""
    names = []
    for name in sorted(os.listdir(folder)):
        stem, ext = os.path.splitext(name)
        if ext.lower() in IMAGE_EXTENSIONS and not stem.endswith("_mask") and os.path.isfile(os.path.join(folder, name)):
            names.append(name)
    return names


def copy_seed(seed, stem, k):
    """The seed of copy k of image stem: the same on every machine and in every order."""
    digest = hashlib.sha256(f"{seed}:{stem}:{k}".encode()).digest()
    return int.from_bytes(digest[:8], "little")


def write_atomic(path, data):
    """Writes bytes through a temporary file in the same folder (created with the usual
    permissions) and a rename: a reader sees the old file or the whole new one, never a part."""
    folder = os.path.dirname(path) or "."
    while True:
        tmp = os.path.join(folder, f".tmp-{os.getpid()}-{os.urandom(6).hex()}-{os.path.basename(path)}")
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
            break
        except FileExistsError:
            continue
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def encode(path, image):
    ok, data = cv2.imencode(os.path.splitext(path)[1], image)
    if not ok:
        raise ValueError(f"cannot encode {os.path.basename(path)}")
    return data.tobytes()


def fallback_cage(size):
    """Where the proposal finds no object: an octagon over the middle of the image."""
    w, h = size
    cx, cy, rx, ry = (w - 1) / 2, (h - 1) / 2, 0.35 * w, 0.35 * h
    angles = np.arange(8) * np.pi / 4 + np.pi / 8
    cage = mc.Multicage((w, h))
    cage.add_polygon(np.stack([cx + rx * np.cos(angles), cy + ry * np.sin(angles)], 1).astype(np.float32))
    return cage


def augment_image(images_dir, name, out_dir, cage_path, copies, seed, amplitude, grid_step, cv_threads):
    """One task: the copies of one image that are not written yet. Returns a line for the log."""
    if cv_threads:
        cv2.setNumThreads(cv_threads)
    stem = os.path.splitext(name)[0]
    outputs = []
    for k in range(copies):
        base = os.path.join(out_dir, f"{stem}_{k:03d}")
        outputs.append((base, f"{base}_mask.png", f"{base}.json"))
    cage_file = os.path.join(out_dir, f"{stem}_cage.yml")
    def done(k, image_ext):
        base, mask, meta = outputs[k]
        return all(os.path.exists(f) for f in (base + image_ext, mask, meta))

    if os.path.exists(cage_file) and (all(done(k, ".png") for k in range(copies)) or
                                      all(done(k, ".tiff") for k in range(copies))):
        return f"{name}: skipped (done)"  # without reading the image
    try:
        # As the CLI reads: a truncated JPEG or PNG, an empty file or a non-image raises
        # multicage.Error (cv2.imread decodes a cut file to grey rows with only a warning).
        image = mc.imread(os.path.join(images_dir, name))
        image_ext = ".tiff" if image.dtype == np.float32 else ".png"
        missing = [k for k in range(copies) if not done(k, image_ext)]
        h, w = image.shape[:2]
        mask_path = os.path.join(images_dir, f"{stem}_mask.png")
        mask = mc.imread(mask_path) if os.path.exists(mask_path) else None
        if mask is not None and mask.shape[:2] != (h, w):
            return f"{name}: error: {stem}_mask.png is {mask.shape[1]}x{mask.shape[0]}, the image {w}x{h}"
        # The proposal's GrabCut draws from OpenCV's random generator, whose state would depend
        # on what this process ran before: seed it per image, so every scheduler agrees.
        cv2.setRNGSeed(copy_seed(seed, stem, -1) % 2**31)
        if cage_path:
            cage = mc.Multicage.load(cage_path)
            cage = cage.scaled((w, h)) if cage.image_size != (w, h) else cage
        else:
            try:
                cage = mc.propose_multicage(image)
            except mc.NoObjectFoundError:
                cage = fallback_cage((w, h))
        if mask is None:
            cv2.setRNGSeed(copy_seed(seed, stem, -2) % 2**31)
            try:
                mask = mc.propose_segmentation(image)
            except mc.Error:
                mask = np.zeros((h, w), np.uint8)
        annotations_path = os.path.join(images_dir, f"{stem}.json")
        annotations = {}
        if os.path.exists(annotations_path):
            with open(annotations_path) as f:
                annotations = json.load(f)
        a = amplitude if amplitude is not None else 0.025 * max(w, h)
        # The transform, with this image's multicage; fold_check='exact' checks every pose on
        # the mesh the copies are deformed with.
        warp = mc.MulticageWarp(amplitude=a, grid_step=grid_step, cage=cage, fold_check="exact")
        keypoints = np.asarray(annotations.get("keypoints", []), np.float32).reshape(-1, 2)
        boxes = np.asarray(annotations.get("boxes", []), np.float32).reshape(-1, 4)
        seeds = [copy_seed(seed, stem, k) for k in range(copies)]
        poses = []
        for k in range(copies):
            # Every copy's pose goes in the cage file; only the missing copies are written.
            out = warp(image=image, mask=mask, keypoints=keypoints, bboxes=boxes, seed=seeds[k],
                       return_params=True)
            poses.append(out["replay"]["pose"])
            if k not in missing:
                continue
            base, mask_file, meta_file = outputs[k]
            meta = {"image": os.path.basename(base + image_ext), "mask": os.path.basename(mask_file),
                    "source": name, "copy": k, "seed": seeds[k], "amplitude": a,
                    "pose": poses[k].tolist(), "keypoints": out["keypoints"].tolist(),
                    "keypoints_visible": out["keypoints_visible"].tolist(), "boxes": out["bboxes"].tolist()}
            write_atomic(base + image_ext, encode(base + image_ext, out["image"]))
            write_atomic(mask_file, encode(mask_file, out["mask"]))
            write_atomic(meta_file, (json.dumps(meta, indent=1) + "\n").encode())  # last: the copy is done
        for k, pose in enumerate(poses):
            cage.add_pose(f"aug{k:03d}", pose)
        cage.save(cage_file)  # atomic too
        return f"{name}: wrote {len(missing)} of {copies} copies"
    except Exception as e:  # one bad image does not stop the others
        return f"{name}: error: {type(e).__name__}: {e}"


def main(argv=None):
    args = parse_args(argv)
    names = list_images(args.images)
    if not names:
        sys.exit(f"dask_augment.py: no images in {args.images}")
    os.makedirs(args.output, exist_ok=True)
    try:
        import dask
        from dask import delayed
    except ImportError as e:
        sys.exit(f"dask_augment.py: {e}; install python3-dask and python3-distributed (Debian) or "
                 "`pip install dask distributed`")
    synchronous = args.scheduler == "synchronous"
    cv_threads = args.cv_threads if args.cv_threads is not None else (0 if synchronous else 1)
    tasks = [delayed(augment_image, pure=True)(args.images, name, args.output, args.cage, args.copies, args.seed,
                                               args.amplitude, args.grid_step, cv_threads)
             for name in names]
    if synchronous:
        lines = dask.compute(*tasks, scheduler="synchronous")
        where = "this process"
    else:
        try:
            from distributed import Client, LocalCluster
        except ImportError as e:
            sys.exit(f"dask_augment.py: {e}; install python3-distributed, or use --scheduler synchronous")
        with tempfile.TemporaryDirectory(prefix="dask-augment-") as scratch:
            if args.scheduler:
                cluster = None
                client = Client(args.scheduler)
                where = f"the cluster at {args.scheduler}"
            else:
                cluster = LocalCluster(n_workers=args.workers or os.cpu_count() or 1, threads_per_worker=1,
                                       processes=True, dashboard_address=None, local_directory=scratch)
                client = Client(cluster)
                where = f"a local cluster of {len(cluster.workers)} worker processes"
            try:
                lines = dask.compute(*tasks)
            finally:
                client.close()
                if cluster is not None:
                    cluster.close()
    for line in lines:
        print(line)
    failed = [name for name, line in zip(names, lines) if line.startswith(f"{name}: error:")]
    skipped = sum(line.endswith("skipped (done)") for line in lines)
    print(f"{len(names)} images on {where}: {len(names) - len(failed) - skipped} augmented, {skipped} skipped "
          f"(already done), {len(failed)} failed{': ' + ', '.join(failed) if failed else ''}; "
          f"outputs in {args.output}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
