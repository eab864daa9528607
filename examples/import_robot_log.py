"""A robot's log made into a softarm recording: `make_robot_log` writes a simulated run as the ROS 2 bag a lab
would record (a 640x480 JPEG camera at 30 Hz, the stretch on the controller's own clock, the motor command as a
JointState), then the importer finds the arm in the images, aligns the clocks and writes a recording that
`softarm train` reads like a simulated one. Replace the first step with your own bag.

    python examples/import_robot_log.py                  # 30 s of arm
    python examples/import_robot_log.py --seconds 6      # a smoke test, seconds
"""

import argparse
from pathlib import Path

import softarm


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--folder", type=Path, default=Path("recordings/example_import"), help="where the files go")
    parser.add_argument("--seconds", type=float, default=30.0, help="seconds of arm to simulate and log")
    args = parser.parse_args()

    native = args.folder / "native.mcap"
    softarm.simulate(softarm.load_config(overrides={"run.duration": args.seconds}), native, force=True)
    log = softarm.make_robot_log(native, args.folder / "lab_bag.mcap")
    print(f"a lab's bag: {log.path} (camera {log.camera_topic}, sensors {log.stretch_topic}, clocks "
          f"{log.offset * 1e3:.0f} ms apart, {len(log.dropped)} camera frames dropped)")

    # What a user gives for their own bag: the image topic, TOPIC:FIELD of the sensors and of the command, and
    # where the arm is in the image (the region of interest, x, y, width, height in the camera's pixels).
    settings = softarm.ImportSettings("/camera/image_raw/compressed", "/arm/stretch:data",
                                      drive="/arm/command:position", roi=log.roi)
    preview = softarm.preview_log(log.path, args.folder / "preview.png", settings, force=True)
    print(f"check the segmentation before a long import: {preview}")

    report = softarm.import_log(log.path, args.folder / "imported.mcap", settings, force=True)
    print(f"imported {report.frames} frames ({report.seconds:.1f} s): camera {report.camera_hz:.1f} Hz, sensors "
          f"{report.sensor_hz:.0f} Hz, the sensors' clock {report.lag * 1e3:+.0f} ms ahead of the camera's, "
          f"{len(report.gaps)} frames without an image")

    imported = softarm.read_recording(report.path)
    print(f"a recording like a simulated one: frames {imported.frames.shape}, stretch {imported.stretch.shape}; "
          f"train it with: softarm train {report.path}")


if __name__ == "__main__":
    main()
