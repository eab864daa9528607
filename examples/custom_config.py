"""A custom config with the world acting on the arm: the paper's drive at a larger amplitude, a poke, a payload from
4 s on and a disc beside the tip, written as a TOML file (what `softarm sim --config` takes) and simulated for a
batch of arms, each of which also draws pokes of its own from its seed.

    python examples/custom_config.py                     # 4 arms, 10 s
    python examples/custom_config.py --seconds 2 --arms 2   # a smoke test
"""

import argparse
from pathlib import Path

import numpy as np

import softarm

CONFIG = """
[excitation]
amplitude = 0.005          # m: a little more than the paper's 4 mm

[[disturbances]]           # a 100 ms poke on row 14, sideways
kind = "push"
start = 1.0
end = 1.1
force = [0.05, 0.0]        # N on each node
nodes = [42, 43, 44]

[[disturbances]]           # 10 g on each tip node from 4 s on: a grasped object
kind = "payload"
start = 4.0
mass = 0.01
nodes = [54, 55, 56]

[[disturbances]]           # a disc beside the tip, the whole run
kind = "obstacle"
start = 0.0
centre = [0.03, -0.16]     # m
radius = 0.012             # m

[[world.random]]           # and every arm draws one to three pokes of its own from its seed
kind = "push"
share = 1.0
count = [1, 3]
start = [0.5, 1.5]
duration = [0.05, 0.15]
force = [0.01, 0.08]
rows = [9, 18]
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--folder", type=Path, default=Path("recordings/example_world"), help="where the files go")
    parser.add_argument("--seconds", type=float, default=10.0, help="seconds to simulate")
    parser.add_argument("--arms", type=int, default=4, help="arms simulated together (arm i uses seed i)")
    args = parser.parse_args()

    args.folder.mkdir(parents=True, exist_ok=True)
    config_file = args.folder / "world.toml"
    config_file.write_text(CONFIG)
    config = softarm.load_config(config_file, overrides={"run.duration": args.seconds, "run.arms": args.arms})
    result = softarm.simulate(config, args.folder / "world.mcap", force=True)
    for path in result.paths:
        recording = softarm.read_recording(path)
        disturbances = recording.model["disturbances"]
        kinds = [d["kind"] for d in disturbances]
        lowest = recording.positions[:, :, 1].min() * 1e3
        print(f"{path.name}: {', '.join(kinds)}; lowest node {lowest:.1f} mm, tip swing "
              f"{np.ptp(recording.positions[:, 55, 0]) * 1e3:.0f} mm")
    print(f"the same from the command line: softarm sim --config {config_file} --duration {args.seconds:g} "
          f"--arms {args.arms}")


if __name__ == "__main__":
    main()
