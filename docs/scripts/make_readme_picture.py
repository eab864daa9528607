"""Makes docs/images/default_run.png: camera frames of a recording at evenly spaced times.

    python docs/scripts/make_readme_picture.py recordings/seed0.mcap
"""

import sys
from pathlib import Path

import numpy as np

from softarm.record.reader import read_recording
from softarm.view.filmstrip import filmstrip, save_png

recording = read_recording(sys.argv[1], nodes=False)
picks = np.linspace(0, len(recording.times) - 1, 10).round().astype(int)[1:]
strip = filmstrip([recording.frames[picks]], ["camera"], recording.times[picks])
print(save_png(strip, Path(__file__).parents[1] / "images" / "default_run.png"))
