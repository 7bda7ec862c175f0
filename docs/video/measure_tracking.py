"""CageTracker on a real clip (docs/video/README.md): how many frames it follows, is lost on or
calls a cut, and the tracked outline's IoU with a fresh proposal every EVERY frames.

Usage, from the repository root after building:
    /usr/bin/python3 docs/video/measure_tracking.py CLIP FRAMES EVERY [KEY=VALUE ...]
KEY=VALUE are CageTracker's options (vertex_correction=0 tracks outlines by similarities alone).
The clips are Debian's opencv-doc (apt-get install opencv-doc, or apt-get download opencv-doc
and dpkg -x it): /usr/share/doc/opencv-doc/examples/data/Megamind.avi and vtest.avi.
"""
import sys
import time

import cv2
import numpy as np
sys.path.insert(0, "build/python")  # run from the repository root
import multicage as mc

path, count, every = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
options = {k: float(v) if "." in v else int(v) for k, v in (a.split("=") for a in sys.argv[4:])}

def outline_mask(cage, shape):
    m = np.zeros(shape[:2], np.uint8)
    for i in range(cage.polygon_count):
        if cage.depth(i) == 1:
            cv2.fillPoly(m, [np.round(cage.polygon(i)).astype(np.int32)], 255)
    return m

def iou(a, b):
    inter = np.count_nonzero(a & b); union = np.count_nonzero(a | b)
    return inter / union if union else 1.0

def propose(frame):
    try:
        return mc.propose_multicage(frame)
    except mc.Error:
        return None  # a black frame, say

v = cv2.VideoCapture(path)
ok, frame = v.read()
tracker = None
states = {"ok": 0, "cut": 0, "lost": 0}
ious, resets, t_track = [], [], 0.0
for t in range(1, count):
    ok, frame = v.read()
    if not ok: break
    if tracker is None:
        cage = propose(frame)
        if cage is not None: tracker = mc.CageTracker(cage, frame, **options)
        continue
    t0 = time.perf_counter(); r = tracker.track(frame); t_track += time.perf_counter() - t0
    states[r["state"]] += 1
    if r["state"] != "ok":
        resets.append((t, r["state"], r["why"][:70]))
        cage = propose(frame)
        tracker = mc.CageTracker(cage, frame, **options) if cage is not None else None
    elif t % every == 0:
        fresh = propose(frame)
        if fresh is not None: ious.append(iou(outline_mask(tracker.multicage, frame.shape), outline_mask(fresh, frame.shape)))
print(path.split("/")[-1], "frames", t, states, "track ms/frame %.1f" % (1000 * t_track / t))
print("IoU tracked vs fresh: n=%d median %.3f min %.3f" % (len(ious), np.median(ious), min(ious)) if ious else "no IoU")
for r in resets[:12]: print("  reset", r)
