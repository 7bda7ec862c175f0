"""VideoReframer on real and composed clips (issue 42, item 5; docs/video/README.md): a clip to
9:16 at its own height (an even width, as `multicage resize --aspect 9:16`), default options,
and what came out:

  faces      every depth >= 2 polygon of every output frame: the largest vertex residual of the
             least-squares similarity rest -> pose (px), and its aspect change (the ratio of the
             singular values of the best affine, minus 1)
  still      GaussianBlur 5x5, sigma 1.5, then the mean absolute grey difference of each output
             frame to the first, the largest (a still clip must stay <= 1); the input's alongside
  smooth     each face followed through a stretch of frames of one shot and one multicage (the
             polygon count and vertex count unchanged): RMS of the second difference of its
             centre, in the input (rest vertices + crop.tl) and in the output (posed vertices),
             px/frame^2; and the output's motion of the background, where the camera is still:
             the change of window x per frame x (output width / window width), px/frame; on
             (c) and (d), whose true motion is known, how far each tracked polygon's centre
             strays from it within a stretch (px)
  IoU        every EVERY-th frame, the tracked outlines (depth 1, of the multicage on the whole
             input frame) filled, against a proposal made afresh on that input frame
             (propose_multicage, defaults), filled
  speed      stats per input frame (ms) and frames per second of the push/pop loop alone

Clips: (a) vtest.avi, (b) Megamind.avi (Debian's opencv-doc: apt-get download opencv-doc and
dpkg -x it; --data points at its examples/data), (c) composed here: a cut-out of astronaut.jpg
(head and shoulders, an elliptical soft mask) crossing building.jpg at 640 x 360, 60 frames,
easing in and out, (d) still: one frame of vtest (--still-frame) held 40 frames, written with
cv2.VideoWriter (H.264, 'avc1', else 'mp4v') and read back, so the codec's noise is in it.

Usage, from the repository root after building:
    /usr/bin/python3 docs/video/measure_reframe.py [--clips abcd] [--frames N] [--figures]
--figures also writes docs/video/reframe_stills.png (input, centre crop, plain scale, ours; one
Megamind and one vtest frame) and docs/video/reframe_strip.gif (ours, every 3rd frame of a
stretch of Megamind) with ffmpeg. --log FILE writes one CSV line per output frame.
"""
import argparse
import csv
import math
import os
import platform
import subprocess
import sys
import tempfile
import time

import cv2
import numpy as np

sys.path.insert(0, "build/python")  # run from the repository root
import multicage as mc

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def even_width(aspect, height):
    """The CLI's --aspect width: 2 * cvRound(aspect * height / 2) (cmd_resize.cpp)."""
    return max(2, 2 * int(round(aspect * height / 2)))


# --- clips -----------------------------------------------------------------------------------

def read_clip(path, limit):
    cap = cv2.VideoCapture(path)
    if not cap.isOpened():
        sys.exit("cannot open " + path)
    count = 0
    while limit <= 0 or count < limit:
        ok, frame = cap.read()
        if not ok:
            break
        count += 1
        yield frame


def composed_motion(t, frames=60, size=(640, 360)):
    """Where the composed clip's cut-out is centred on frame t (its true motion)."""
    w, h = size
    s = t / (frames - 1)
    return np.array([130 + (w - 260) * (1 - math.cos(math.pi * s)) / 2,  # eases in and out
                     h / 2 + 12 + 8 * math.sin(2 * math.pi * s)])


def composed_clip(frames=60, size=(640, 360)):
    """astronaut.jpg's head and shoulders, soft elliptical mask, crossing building.jpg."""
    w, h = size
    bg = cv2.imread(os.path.join(ROOT, "..", "shared", "data", "images", "building.jpg"))
    if bg is None:
        bg = cv2.imread(os.path.join(ROOT, "samples", "data", "propose_bench", "coffee.jpg"))
    bh = int(bg.shape[1] * h / w)  # a 16:9 band of it
    y0 = max(0, (bg.shape[0] - bh) // 2)
    bg = cv2.resize(bg[y0:y0 + bh], (w, h), interpolation=cv2.INTER_AREA)
    person = cv2.imread(os.path.join(ROOT, "samples", "data", "propose_bench", "astronaut.jpg"))
    person = person[0:320, 90:350]  # head and shoulders, 260 x 320
    scale = 0.75
    person = cv2.resize(person, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA)
    ph, pw = person.shape[:2]
    mask = np.zeros((ph, pw), np.float32)
    cv2.ellipse(mask, (pw // 2, ph // 2), (pw // 2 - 8, ph // 2 - 6), 0, 0, 360, 1.0, -1)
    mask = cv2.GaussianBlur(mask, (0, 0), 5)[..., None]
    person = person.astype(np.float32)
    for t in range(frames):
        cx, cy = composed_motion(t, frames, size)
        # whole-pixel placement through a warp, so the motion is sub-pixel smooth
        m = np.float32([[1, 0, cx - pw / 2], [0, 1, cy - ph / 2]])
        fg = cv2.warpAffine(person, m, (w, h), flags=cv2.INTER_LINEAR)
        a = cv2.warpAffine(mask, m, (w, h), flags=cv2.INTER_LINEAR)[..., None]
        yield np.clip(fg * a + bg.astype(np.float32) * (1 - a) + 0.5, 0, 255).astype(np.uint8)


def still_clip(vtest, index, frames=40, workdir="/work/clips/measure"):
    """One frame of vtest held `frames` frames, through the codec and back."""
    frame = None
    for i, f in enumerate(read_clip(vtest, index + 1)):
        frame = f
    os.makedirs(workdir, exist_ok=True)
    h, w = frame.shape[:2]
    for fourcc in ("avc1", "mp4v"):
        path = os.path.join(workdir, "still_%s.mp4" % fourcc)
        writer = cv2.VideoWriter(path, cv2.VideoWriter_fourcc(*fourcc), 10, (w, h))
        if writer.isOpened():
            break
    for _ in range(frames):
        writer.write(frame)
    writer.release()
    return path, fourcc


# --- measures --------------------------------------------------------------------------------

def similarity_residual(rest, posed):
    """Largest vertex residual of the least-squares similarity rest -> posed, and the aspect
    change of the best affine (larger over smaller singular value, minus 1)."""
    z = rest[:, 0] + 1j * rest[:, 1]
    v = posed[:, 0] + 1j * posed[:, 1]
    zc, vc = z - z.mean(), v - v.mean()
    a = np.vdot(zc, vc) / np.vdot(zc, zc).real
    residual = float(np.abs(a * zc - vc).max())
    A = np.c_[rest, np.ones(len(rest))]
    m = np.linalg.lstsq(A, posed, rcond=None)[0][:2].T
    s = np.linalg.svd(m, compute_uv=False)
    return residual, float(s[0] / s[1] - 1)


def outline_mask(cage, shape, offset=(0, 0)):
    m = np.zeros(shape[:2], np.uint8)
    for i in range(cage.polygon_count):
        if cage.depth(i) == 1:
            p = cage.polygon(i) + np.float32(offset)
            cv2.fillPoly(m, [np.round(p).astype(np.int32)], 255)
    return m > 0


def blur_grey(image):
    g = cv2.cvtColor(image, cv2.COLOR_BGR2GRAY) if image.ndim == 3 else image
    return cv2.GaussianBlur(g, (5, 5), 1.5).astype(np.float32)


def rms(values):
    return float(np.sqrt(np.mean(np.square(values)))) if len(values) else float("nan")


class Measure:
    """Everything measured on one clip, fed one output frame at a time."""

    def __init__(self, name, every, log=None, truth=None):
        self.name, self.every, self.log, self.truth = name, every, log, truth
        self.drift_base = {}  # polygon index -> (its centre, the truth) on the stretch's first
        self.drift = (0.0, -1)
        self.empty = self.faceless = 0
        self.faces = 0
        self.worst_res = (0.0, -1)
        self.worst_aspect = (0.0, -1)
        self.over_1px = 0
        self.first_out = self.first_in = None
        self.still_out = (0.0, -1)
        self.still_in = (0.0, -1)
        self.tracks = {}  # polygon index -> ([input centres], [output centres], [frame indices])
        self.key = None   # (shot, polygon count, vertex count) of the current stretch
        self.acc_in, self.acc_out = [], []
        self.worst_acc = []  # (output acceleration, frame, polygon)
        self.stretches = 0
        self.prev_window = None
        self.bg_v = []
        self.bg_acc = []
        self.worst_bg = (0.0, -1)
        self.ious, self.iou_worst, self.iou_skipped = [], (1.0, -1), 0

    def _close_stretch(self):
        for pin, pout, idx in self.tracks.values():
            if len(pin) >= 3:
                pin, pout = np.array(pin), np.array(pout)
                ain = np.linalg.norm(pin[2:] - 2 * pin[1:-1] + pin[:-2], axis=1)
                aout = np.linalg.norm(pout[2:] - 2 * pout[1:-1] + pout[:-2], axis=1)
                self.acc_in.extend(ain)
                self.acc_out.extend(aout)
                k = int(np.argmax(aout))
                self.worst_acc.append((float(aout[k]), idx[k + 1]))
        if self.tracks:
            self.stretches += 1
        self.tracks = {}
        self.drift_base = {}

    def add(self, out, frame_in):
        cage, pose, index = out["cage"], out["pose"], out["index"]
        cx, cy = out["crop"][:2]
        worst_here = 0.0
        key = (out["shot"], cage.polygon_count, cage.vertex_count)
        if key != self.key:
            self._close_stretch()
            self.key = key
        faces = sum(cage.depth(i) >= 2 for i in range(cage.polygon_count))
        self.empty += cage.polygon_count == 0
        self.faceless += faces == 0
        if self.truth is not None:  # the tracked centres against the true motion
            for i in range(cage.polygon_count):
                c = cage.polygon(i).astype(np.float64).mean(0) + (cx, cy)
                base = self.drift_base.setdefault(i, (c, self.truth(index)))
                e = float(np.linalg.norm((c - base[0]) - (self.truth(index) - base[1])))
                if e > self.drift[0]:
                    self.drift = (e, index)
        for i in range(cage.polygon_count):
            if cage.depth(i) < 2:
                continue
            rest = cage.polygon(i).astype(np.float64)
            off = cage.polygon_offset(i)
            posed = pose[off:off + len(rest)].astype(np.float64)
            r, asp = similarity_residual(rest, posed)
            self.faces += 1
            worst_here = max(worst_here, r)
            if r > 1.0:
                self.over_1px += 1
            if r > self.worst_res[0]:
                self.worst_res = (r, index)
            if asp > self.worst_aspect[0]:
                self.worst_aspect = (asp, index)
            t = self.tracks.setdefault(i, ([], [], []))
            t[0].append(rest.mean(0) + (cx, cy))
            t[1].append(posed.mean(0))
            t[2].append(index)
        # stillness
        g = blur_grey(out["image"])
        if self.first_out is None:
            self.first_out = g
        d = float(np.abs(g - self.first_out).mean())
        if d > self.still_out[0]:
            self.still_out = (d, index)
        if frame_in is not None:
            gi = blur_grey(frame_in)
            if self.first_in is None:
                self.first_in = gi
            di = float(np.abs(gi - self.first_in).mean())
            if di > self.still_in[0]:
                self.still_in = (di, index)
        # the background's motion on the output
        wx, _, ww, _ = out["window"]
        if self.prev_window is not None and self.prev_window[0] == out["shot"]:
            v = (wx - self.prev_window[1]) * out["image"].shape[1] / ww
            if self.bg_v and self.prev_window[2] is not None:
                self.bg_acc.append(v - self.prev_window[2])
            self.bg_v.append(v)
            if abs(v) > self.worst_bg[0]:
                self.worst_bg = (abs(v), index)
            self.prev_window = (out["shot"], wx, v)
        else:
            self.prev_window = (out["shot"], wx, None)
        if self.log is not None:
            self.log.writerow([self.name, index, out["shot"], "%.2f" % wx, "%.2f" % ww,
                               cage.polygon_count, faces,
                               "%.3f" % worst_here, int(out["smoothed"]), "%.2f" % d])

    def add_iou(self, out, frame_in):
        # The tracked multicage on the whole frame (the crop drops the polygons it cuts).
        tracked = outline_mask(out["tracked"], frame_in.shape, (0, 0))
        try:
            fresh = outline_mask(mc.propose_multicage(frame_in), frame_in.shape)
        except mc.Error:
            fresh = np.zeros_like(tracked)
        union = np.count_nonzero(tracked | fresh)
        if union == 0:
            self.iou_skipped += 1
            return
        iou = np.count_nonzero(tracked & fresh) / union
        self.ious.append(iou)
        if iou < self.iou_worst[0] or self.iou_worst[1] < 0:
            self.iou_worst = (iou, out["index"])

    def finish(self):
        self._close_stretch()


def run_clip(name, frames, aspect, every, keep=(), log=None, keep_inputs=(), truth=None):
    """Reframes `frames`; returns (Measure, stats, size, n, loop seconds, kept outputs, kept
    inputs)."""
    reframer = None
    m = Measure(name, every, log, truth)
    pending = {}  # input frames still needed: index -> frame
    kept, kept_in = {}, {}
    loop = 0.0
    n = 0
    size = None

    def drain():
        nonlocal loop
        while True:
            t0 = time.perf_counter()
            out = reframer.pop()
            loop += time.perf_counter() - t0
            if out is None:
                return
            i = out["index"]
            m.add(out, pending.get(i))
            if i % every == 0 and i in pending:
                m.add_iou(out, pending[i])
            pending.pop(i, None)
            if i in keep:
                kept[i] = out["image"]

    for frame in frames:
        if reframer is None:
            h = frame.shape[0]
            size = (even_width(aspect, h), h)
            reframer = mc.VideoReframer(size)
        pending[n] = frame
        if n in keep_inputs:
            kept_in[n] = frame
        t0 = time.perf_counter()
        reframer.push(frame)
        loop += time.perf_counter() - t0
        n += 1
        drain()
    t0 = time.perf_counter()
    reframer.finish()
    loop += time.perf_counter() - t0
    drain()
    m.finish()
    return m, reframer.stats, size, n, loop, kept, kept_in


# --- figures ---------------------------------------------------------------------------------

def label(img, text):
    img = img.copy()
    for colour, thick in (((0, 0, 0), 3), ((255, 255, 255), 1)):
        cv2.putText(img, text, (4, 14), cv2.FONT_HERSHEY_SIMPLEX, 0.42, colour, thick,
                    cv2.LINE_AA)
    return img


def panels(frame, ours, height):
    h, w = frame.shape[:2]
    ow = ours.shape[1]
    x = (w - ow) // 2  # ffmpeg's crop=ow:h centres it
    centre = frame[:, x:x + ow]
    scaled = cv2.resize(frame, (ow, h), interpolation=cv2.INTER_AREA)

    def fit(img):
        return cv2.resize(img, (max(1, round(img.shape[1] * height / img.shape[0])), height),
                          interpolation=cv2.INTER_AREA)

    gap = np.full((height, 4, 3), 255, np.uint8)
    row = [label(fit(frame), "input %dx%d" % (w, h)), gap,
           label(fit(centre), "centre crop"), gap,
           label(fit(scaled), "scale"), gap,
           label(fit(ours), "multicage")]
    return np.hstack(row)


def write_png_small(image, path, limit=300_000):
    cv2.imwrite(path, image, [cv2.IMWRITE_PNG_COMPRESSION, 9])
    if os.path.getsize(path) > limit:  # 256 colours (ffmpeg's palette), still a PNG
        with tempfile.TemporaryDirectory() as tmp:
            src = os.path.join(tmp, "in.png")
            cv2.imwrite(src, image)
            subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", src, "-vf",
                            "split[a][b];[a]palettegen=max_colors=256[p];[b][p]paletteuse="
                            "dither=none", "-pix_fmt", "pal8", path], check=True)
    return os.path.getsize(path)


def write_gif(images, path, fps, width):
    with tempfile.TemporaryDirectory() as tmp:
        for k, img in enumerate(images):
            cv2.imwrite(os.path.join(tmp, "%03d.png" % k), img)
        subprocess.run(["ffmpeg", "-v", "error", "-y", "-framerate", str(fps), "-i",
                        os.path.join(tmp, "%03d.png"), "-vf",
                        "scale=%d:-2:flags=area,split[a][b];[a]palettegen=max_colors=128[p];"
                        "[b][p]paletteuse=dither=bayer:bayer_scale=3" % width,
                        "-loop", "0", path], check=True)
    return os.path.getsize(path)


# --- main ------------------------------------------------------------------------------------

def fmt(value, spec="%.2f"):
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "-"
    return spec % value


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", default="/work/clips/x/usr/share/doc/opencv-doc/examples/data",
                    help="folder of vtest.avi and Megamind.avi (opencv-doc's examples/data)")
    ap.add_argument("--clips", default="abcd", help="which of a (vtest), b (Megamind), "
                    "c (composed), d (still); default all")
    ap.add_argument("--frames", type=int, default=300,
                    help="at most this many frames of each file clip (0: all; default 300)")
    ap.add_argument("--every", type=int, default=10, help="IoU every this many frames")
    ap.add_argument("--aspect", default="9:16", help="output aspect w:h (height kept)")
    ap.add_argument("--still-frame", type=int, default=120, help="vtest frame held in (d)")
    ap.add_argument("--figures", action="store_true",
                    help="also write reframe_stills.png and reframe_strip.gif here")
    ap.add_argument("--mm-frame", type=int, default=130, help="Megamind frame of the stills")
    ap.add_argument("--vt-frame", type=int, default=30, help="vtest frame of the stills")
    ap.add_argument("--strip", default="36:84:3", help="Megamind frames of the GIF, a:b:step")
    ap.add_argument("--log", help="CSV, one line per output frame")
    a = ap.parse_args()
    aw, ah = (float(x) for x in a.aspect.split(":"))
    aspect = aw / ah
    vtest = os.path.join(a.data, "vtest.avi")
    mega = os.path.join(a.data, "Megamind.avi")
    s0, s1, s2 = (int(x) for x in a.strip.split(":"))
    strip = set(range(s0, s1, s2)) if a.figures else set()
    log = None
    if a.log:
        logfile = open(a.log, "w", newline="")
        log = csv.writer(logfile)
        log.writerow(["clip", "index", "shot", "window_x", "window_w", "polygons", "faces",
                      "worst_residual", "smoothed", "still_diff"])

    clips = []
    if "a" in a.clips:
        clips.append(("a vtest", lambda: read_clip(vtest, a.frames),
                      {a.vt_frame} if a.figures else set(), None))
    if "b" in a.clips:
        clips.append(("b Megamind", lambda: read_clip(mega, a.frames),
                      ({a.mm_frame} | strip) if a.figures else set(), None))
    if "c" in a.clips:
        clips.append(("c composed", composed_clip, set(), composed_motion))
    if "d" in a.clips:
        path, fourcc = still_clip(vtest, a.still_frame)
        clips.append(("d still (%s)" % fourcc, lambda: read_clip(path, 0), set(),
                      lambda t: np.zeros(2)))

    t_start = time.perf_counter()
    results = []
    kept_out, kept_in = {}, {}
    for name, frames, keep, truth in clips:
        fig_in = keep & {a.mm_frame, a.vt_frame}
        res = run_clip(name, frames(), aspect, a.every, keep, log, fig_in, truth)
        results.append((name,) + res)
        kept_out[name], kept_in[name] = res[5], res[6]
        print("  %s: %d frames in %.1f s" % (name, res[3], time.perf_counter() - t_start),
              file=sys.stderr, flush=True)
    wall = time.perf_counter() - t_start

    rows = [
        ("frames in -> output size", lambda m, s, size, n, t: "%d -> %dx%d" % (n, *size)),
        ("frames with no polygon / no face", lambda m, s, size, n, t: "%d / %d" % (m.empty,
                                                                                m.faceless)),
        ("1 faces measured (polygon x frame)", lambda m, s, size, n, t: "%d" % m.faces),
        ("1 worst similarity residual px (frame)",
         lambda m, s, size, n, t: "%s (%d)" % (fmt(m.worst_res[0], "%.3f"), m.worst_res[1])
         if m.faces else "-"),
        ("1 faces over 1 px",
         lambda m, s, size, n, t: "%d" % m.over_1px if m.faces else "-"),
        ("1 worst aspect change % (frame)",
         lambda m, s, size, n, t: "%s (%d)" % (fmt(100 * m.worst_aspect[0]), m.worst_aspect[1])
         if m.faces else "-"),
        ("2 still: max mean |grey diff| out (in)",
         lambda m, s, size, n, t: "%.2f (%.2f)" % (m.still_out[0], m.still_in[0])),
        ("3 face stretches / samples",
         lambda m, s, size, n, t: "%d / %d" % (m.stretches, len(m.acc_out))),
        ("3 face RMS accel in -> out px/f^2",
         lambda m, s, size, n, t: "%s -> %s" % (fmt(rms(m.acc_in)), fmt(rms(m.acc_out)))),
        ("3 face worst accel out (frame)",
         lambda m, s, size, n, t: "%.2f (%d)" % max(m.worst_acc) if m.worst_acc else "-"),
        ("3 tracked centre vs true motion px (frame)",
         lambda m, s, size, n, t: "%.2f (%d)" % m.drift if m.truth is not None else "-"),
        ("3 background mean |v| px/f",
         lambda m, s, size, n, t: fmt(float(np.mean(np.abs(m.bg_v))) if m.bg_v else None)),
        ("3 background RMS accel px/f^2", lambda m, s, size, n, t: fmt(rms(m.bg_acc))),
        ("3 background max |v| px/f (frame)",
         lambda m, s, size, n, t: "%.2f (%d)" % m.worst_bg),
        ("4 IoU median (min, frame) n",
         lambda m, s, size, n, t: "%s (%s, %d) %d" % (fmt(float(np.median(m.ious))),
                                                      fmt(m.iou_worst[0]), m.iou_worst[1],
                                                      len(m.ious)) if m.ious else "-"),
        ("4 proposals / cuts / lost / unsmoothed",
         lambda m, s, size, n, t: "%d / %d / %d / %d" % (s["proposals"], s["cuts"], s["lost"],
                                                         s["unsmoothed"])),
        ("5 ms/frame track / propose / bind",
         lambda m, s, size, n, t: "%.1f / %.1f / %.1f" % (s["track_ms"] / n,
                                                          s["propose_ms"] / n, s["bind_ms"] / n)),
        ("5 ms/frame pose / deform",
         lambda m, s, size, n, t: "%.1f / %.1f" % (s["pose_ms"] / n, s["deform_ms"] / n)),
        ("5 fps, push/pop loop", lambda m, s, size, n, t: "%.1f" % (n / t)),
    ]
    cols = [[r[0] for r in rows]]
    heads = ["figure"]
    for name, m, s, size, n, t, _, _ in results:
        heads.append(name)
        cols.append([f(m, s, size, n, t) for _, f in rows])
    widths = [max(len(h), *(len(c) for c in col)) for h, col in zip(heads, cols)]
    print("VideoReframer, each clip -> %s at its height, default options; %s, %d cores, "
          "OpenCV %s; %.0f s in all" % (a.aspect, platform.node() or "?",
                                        os.cpu_count(), cv2.__version__, wall))
    print("| " + " | ".join(h.ljust(w) for h, w in zip(heads, widths)) + " |")
    print("|" + "|".join("-" * (w + 2) for w in widths) + "|")
    for k in range(len(rows)):
        print("| " + " | ".join(col[k].ljust(w) for col, w in zip(cols, widths)) + " |")

    if a.figures:
        out_png = os.path.join(HERE, "reframe_stills.png")
        out_gif = os.path.join(HERE, "reframe_strip.gif")
        rows_img = []
        for name, idx in (("b Megamind", a.mm_frame), ("a vtest", a.vt_frame)):
            if idx in kept_out.get(name, {}) and idx in kept_in.get(name, {}):
                rows_img.append(panels(kept_in[name][idx], kept_out[name][idx], 240))
        if rows_img:
            width = max(r.shape[1] for r in rows_img)
            rows_img = [np.hstack([r, np.full((r.shape[0], width - r.shape[1], 3), 255,
                                              np.uint8)]) for r in rows_img]
            sep = np.full((4, width, 3), 255, np.uint8)
            img = np.vstack(sum(([r, sep] for r in rows_img), [])[:-1])
            print("wrote %s (%d bytes)" % (out_png, write_png_small(img, out_png)))
        frames = [kept_out["b Megamind"][i] for i in sorted(strip)
                  if i in kept_out.get("b Megamind", {})]
        if frames:
            print("wrote %s (%d frames, %d bytes)" % (out_gif, len(frames),
                                                     write_gif(frames, out_gif, 8, 160)))
    if log is not None:
        logfile.close()


if __name__ == "__main__":
    main()
