"""Speed of reframing a clip (issue 42 item 6): `multicage resize CLIP --aspect 9:16` per frame
and in all, with its stages, beside what people use today on the same clip in the same run:
ffmpeg's crop and scale (a moving crop tool's floor) and ImageMagick's liquid rescale (seam
carving) per frame.

Usage, from the repository root after building:
    /usr/bin/python3 docs/video/bench_reframe.py CLIP [--runs 3] [--lqr-frames 5]
A 1280x720 clip from Debian's opencv-doc (docs/video/README.md says how):
    ffmpeg -i /usr/share/doc/opencv-doc/examples/data/vtest.avi -vf scale=1280:720 \\
        -c:v libx264 -pix_fmt yuv420p vt720.mp4
ImageMagick (apt-get install imagemagick; Debian's has the liquid rescale delegate) and ffmpeg
are optional: a missing one is said and skipped.
"""
import argparse
import pathlib
import re
import shutil
import statistics
import subprocess
import tempfile
import time

CLI = "build/bin/multicage"


def machine():
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return "unknown CPU"


def frames_of(clip):
    r = subprocess.run(["ffprobe", "-v", "error", "-select_streams", "v:0", "-count_packets",
                        "-show_entries", "stream=nb_read_packets,width,height", "-of", "csv=p=0",
                        clip], capture_output=True, text=True, check=True)
    w, h, n = (int(v) for v in r.stdout.strip().split(","))
    return w, h, n


def timed(cmd):
    t = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{r.stderr}")
    return time.perf_counter() - t, r.stdout


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("clip")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--lqr-frames", type=int, default=5)
    a = ap.parse_args()
    w, h, n = frames_of(a.clip)
    ow = 2 * round(9 / 16 * h / 2)
    work = pathlib.Path(tempfile.mkdtemp(prefix="bench_reframe_"))
    print(f"{a.clip}: {w}x{h}, {n} frames -> {ow}x{h} (9:16); {machine()}, "
          f"{len(open('/proc/cpuinfo').read().split('processor')) - 1} cores; median of {a.runs} runs")
    rows = []
    ours, stages = [], []
    for _ in range(a.runs):
        s, out = timed([CLI, "resize", a.clip, "-o", str(work / "ours.mp4"), "--aspect", "9:16"])
        ours.append(s)
        stages.append(re.search(r"per frame: (.*) ms", out).group(1))
    rows.append(("multicage resize (ours)", statistics.median(ours)))
    ffmpeg = shutil.which("ffmpeg")
    for name, vf in (("ffmpeg crop (centre)", f"crop={ow}:{h}"), ("ffmpeg scale (squash)", f"scale={ow}:{h}")):
        if not ffmpeg:
            print(f"{name}: ffmpeg is not installed, skipped")
            continue
        runs = [timed([ffmpeg, "-loglevel", "error", "-y", "-i", a.clip, "-vf", vf, "-an", "-c:v",
                       "libx264", "-pix_fmt", "yuv420p", str(work / "peer.mp4")])[0]
                for _ in range(a.runs)]
        rows.append((name, statistics.median(runs)))
    convert = shutil.which("convert-im6.q16") or "/usr/bin/convert"
    if ffmpeg and pathlib.Path(convert).exists():
        subprocess.run([ffmpeg, "-loglevel", "error", "-y", "-i", a.clip, "-frames:v",
                        str(a.lqr_frames), str(work / "f%03d.png")], check=True)
        per = [timed([convert, str(f), "-liquid-rescale", f"{ow}x{h}!", str(work / "lqr.png")])[0]
               for f in sorted(work.glob("f*.png"))]
        rows.append((f"ImageMagick -liquid-rescale ({len(per)} frames, x {n})",
                     statistics.median(per) * n))
    else:
        print("ImageMagick is not installed (apt-get install imagemagick): liquid rescale skipped")
    print(f"{'':44s} {'whole clip':>11s} {'per frame':>10s} {'frames/s':>9s}")
    for name, s in rows:
        print(f"{name:44s} {s:10.1f}s {1000 * s / n:8.1f}ms {n / s:9.1f}")
    print("ours per frame (each run):")
    for s in stages:
        print("  " + s + " ms")
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
