"""What the Python samples import (cv2, numpy, multicage), in one place: where one is missing,
the sample stops with one line saying what to install or which PYTHONPATH to set.

    from sample_imports import cv2, np, multicage    # beside the sample, as installed
"""

import os
import sys


def _stop(why):
    sys.exit(f"{os.path.basename(sys.argv[0]) or 'python'}: {why}")


try:
    import cv2
    import numpy as np
except ImportError as e:
    _stop(f"{e}; install python3-opencv and python3-numpy")
try:
    import multicage
except ImportError as e:
    _stop(f"cannot import multicage ({e}); from a build tree run with PYTHONPATH=<build>/python, "
          "after install with PYTHONPATH=<prefix>/lib/python3.X/dist-packages")

__all__ = ["cv2", "np", "multicage"]
