"""`softarm import` and `softarm robot-log`: a real robot's MCAP log made into a softarm recording, and a
robot-style log made from a softarm recording for trying that out."""

from pathlib import Path
from typing import Annotated, Any, Optional

import typer
from softarm_cli.console import complain, err, run_or_exit, say
from softarm_cli.options import Force, Quiet

from softarm.real.settings import ImportSettings, parse_frame_dt, parse_roi

MASK_HELP = ("Which pixels are arm: auto (the Otsu rule that separates best, then a cut over the colours fitted to its "
             "classes, cleaned), CHANNEL>VALUE or CHANNEL<VALUE (channels r g b gray h s v, or diff and chroma against "
             "the background; VALUE a number 0..255, hue in degrees, or otsu), hsv=H0-H1,S0-S1,V0-V1, or "
             "rgb=WR,WG,WB>CUT (WR r + WG g + WB b > CUT).")


def import_log(
    log: Annotated[Path, typer.Argument(metavar="LOG", help="A robot's log: an MCAP file (ROS 2 or Foxglove), a ROS 1 .bag or a ROS 2 bag folder (sqlite3 or MCAP storage).")],
    camera: Annotated[str, typer.Option(help="Image topic (sensor_msgs Image / CompressedImage, foxglove RawImage / CompressedImage).")],
    sensors: Annotated[str, typer.Option(help="Stretch readings as TOPIC:FIELD, e.g. /arm/stretch:data or /joint_states:position.")],
    out_path: Annotated[Optional[Path], typer.Option("--out", "-o", help="The softarm recording to write (.mcap).")] = None,
    drive: Annotated[Optional[str], typer.Option(help="The actuator command as TOPIC:FIELD, on the sensors' clock.")] = None,
    mask: Annotated[str, typer.Option(help=MASK_HELP)] = "auto",
    background: Annotated[Optional[str], typer.Option(help="Subtract a background: 'median' of frames across the log, or an image file.")] = None,
    roi: Annotated[Optional[str], typer.Option(help="Region of interest X,Y,WIDTH,HEIGHT in the camera's pixels, cut before resizing.")] = None,
    frame_dt: Annotated[Optional[str], typer.Option(help="Frame period of the recording in s, or 'camera' for the camera's own; frames between camera images are gaps [default: the config's integration.frame_dt, the stretch's usual rate].")] = None,
    lag: Annotated[Optional[float], typer.Option(help="Seconds the sensors' stamps run ahead of the camera's [default: found by cross-correlation].")] = None,
    scale: Annotated[Optional[float], typer.Option(help="The camera's pixels per metre in the arm's plane, for tip errors in mm.")] = None,
    arm_length: Annotated[Optional[float], typer.Option(help="The arm's length as it hangs at rest, top to tip, in m: the scale from the masks, for tip errors in mm.")] = None,
    max_lag: Annotated[float, typer.Option(help="The lag is searched within +-this many seconds.")] = ImportSettings.max_lag,
    preview: Annotated[Optional[Path], typer.Option(help="Write a PNG of a few frames and their masks, and stop (nothing is converted).")] = None,
    force: Force = False,
    quiet: Quiet = False,
) -> None:
    """Import a robot's log: camera frames segmented into masks, sensors aligned to them, as a softarm recording.

    \b
    Example: softarm import lab.mcap --camera /camera/image_raw/compressed --sensors /arm/stretch:data --roi 26,58,588,364 --preview mask.png
             softarm import lab.mcap --camera /camera/image_raw/compressed --sensors /arm/stretch:data --roi 26,58,588,364 --out lab.mcap
    """
    from softarm.real.convert import import_log as convert
    from softarm.real.preview import preview_log

    settings = run_or_exit(lambda: ImportSettings(camera, sensors, drive, mask, background, parse_roi(roi),
                                                  frame_dt=parse_frame_dt(frame_dt), lag=lag, max_lag=max_lag,
                                                  scale=scale, arm_length=arm_length))
    if preview is not None:
        written = run_or_exit(lambda: preview_log(log, preview, settings, force=force))
        if not quiet:
            say(f"wrote {written}: camera, mask over it, mask at the models' size")
        return
    if out_path is None:
        complain("error: give --out REC.mcap to convert (or --preview PNG to look at the masks first)")
        raise typer.Exit(2)
    report = run_or_exit(lambda: convert(log, out_path, settings, force=force))
    if not quiet:
        say_import(report, scale is not None)


def say_import(report: Any, scale_given: bool) -> None:
    """What the import found: rates, lag, overlap and gaps, the mask, the scale."""
    drive_rate = f", drive {report.drive_hz:.1f} Hz" if report.drive_hz is not None else ""
    how = "found by cross-correlation" + (f", R^2 {report.lag_fit:.2f}" if report.lag_fit is not None else "")
    say(f"rates: camera {report.camera_hz:.2f} Hz, sensors {report.sensor_hz:.1f} Hz{drive_rate}")
    say(f"lag: sensors {report.lag * 1e3:+.1f} ms ahead of the camera ({how if report.lag_estimated else 'given'})")
    say(f"overlap: {report.overlap[0]:.3f}..{report.overlap[1]:.3f} s of the camera's time; "
              f"{report.frames} frames every {report.frame_dt * 1e3:.2f} ms, {report.frames - len(report.gaps)} with a "
              f"camera image ({len(report.gaps)} without: training skips them); the camera dropped {report.dropped} frame(s)")
    otsu = f"Otsu threshold {report.threshold:.0f}" if report.threshold is not None else ""
    if report.auto_rule is not None:
        cut = f", cut over colour as {report.rule}" if report.rule != report.auto_rule else ""
        say(f"mask: auto chose {report.auto_rule} ({otsu}, separability {report.separability:.2f}){cut}; "
            f"{report.coverage:.1%} of pixels are arm")
    else:
        say(f"mask: {report.coverage:.1%} of pixels are arm" + (f" ({otsu})" if otsu else ""))
    if report.pixels_per_metre is not None:
        say(f"scale: {report.pixels_per_metre:.1f} px/m in the recording's frames "
            f"({'from --scale' if scale_given else 'from --arm-length and the masks'})")
    say(f"wrote {report.path}")


def robot_log(
    recording: Annotated[Path, typer.Argument(metavar="RECORDING.mcap", help="A softarm recording.")],
    out_path: Annotated[Path, typer.Option("--out", "-o", help="The ROS 2 MCAP log to write.")],
    image_format: Annotated[str, typer.Option(help="jpeg | png | rgb8")] = "jpeg",
    offset: Annotated[float, typer.Option(help="Seconds the sensor clock runs ahead of the camera's.")] = 0.047,
    dropped: Annotated[int, typer.Option(help="Camera frames dropped.")] = 5,
    arm_colour: Annotated[str, typer.Option(help="The arm's colour R,G,B (0..255).")] = "215,95,35",
    scene_colour: Annotated[str, typer.Option(help="The background's mean colour R,G,B (0..255).")] = "98,128,126",
    texture: Annotated[float, typer.Option(help="The background's texture, 0 (flat) to 3; 1 is a lab wall's.")] = 1.0,
    lighting_drift: Annotated[float, typer.Option(help="The light's level drifts from 1 - this to 1 + this over the run (0..0.9).")] = 0.0,
    motion_blur: Annotated[float, typer.Option(help="Exposure time in s: the moving arm is smeared over it (0..0.2).")] = 0.0,
    distractor: Annotated[bool, typer.Option(help="A second object swinging across the scene behind the arm.")] = False,
    seed: Annotated[int, typer.Option(help="Seed of the scene, the noise, the dropped frames and the jitter.")] = 0,
    force: Force = False,
    quiet: Quiet = False,
) -> None:
    """Write a softarm recording as the ROS 2 bag a lab would log (640x480 colour camera at 30 Hz, stretch at 100 Hz
    on a clock of its own, the drive): something to try `softarm import` on, in scenes unlike the default one.

    \b
    Example: softarm robot-log recordings/seed0.mcap --out recordings/seed0_robot.mcap
             softarm robot-log recordings/seed0.mcap --out recordings/seed0_dark.mcap --arm-colour 40,35,45 --scene-colour 200,200,190 --lighting-drift 0.3 --distractor
    """
    from softarm.real.robot_log import RobotLogSettings, make_robot_log
    from softarm.real.robot_settings import parse_rgb

    settings = run_or_exit(lambda: RobotLogSettings(
        image_format=image_format, sensor_offset=offset, dropped=dropped, arm_rgb=parse_rgb(arm_colour, "--arm-colour"),
        scene_rgb=parse_rgb(scene_colour, "--scene-colour"), texture=texture, lighting_drift=lighting_drift,
        motion_blur=motion_blur, distractor=distractor, seed=seed))
    made = run_or_exit(lambda: make_robot_log(recording, out_path, settings, force=force))
    if not quiet:
        say_robot_log(made)


def say_robot_log(made: Any) -> None:
    """What a robot log holds, and what `softarm import` should be given to read it."""
    say(f"wrote {made.path}: {made.frames} camera frames on {made.camera_topic}, stretch on "
        f"{made.stretch_topic}, drive on {made.drive_topic}; the arm is in --roi {','.join(map(str, made.roi))}")
    err.print(f"sensor clock {made.offset * 1e3:+.0f} ms ahead of the camera; {len(made.dropped)} frame(s) dropped; "
              f"the camera's scale in the arm's plane: --scale {made.pixels_per_metre:g}")
