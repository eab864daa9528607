"""Rich tables of the metrics dictionaries that training and replay return."""

from typing import Any, Optional

from rich.table import Table

ROWS = {"model": "model imagination", "ridge": "ridge baseline", "mean_frame": "mean-frame baseline",
        "ae_ceiling": "AE ceiling (true latent)"}


def scores_row(table: Table, label: str, scores: dict[str, float]) -> None:
    """One row of BCE, IoU, Dice and tip error."""
    table.add_row(label, f"{scores['bce']:.4f}", f"{scores['iou']:.3f}", f"{scores['dice']:.3f}",
                  f"{scores['tip_mm']:.1f}")


def metrics_table(metrics: dict[str, Any]) -> Table:
    """Training's held-out scores beside the baselines, as the README's results table."""
    counts = metrics["counts"]
    table = Table(title=f"held-out metrics ({counts['imagination_predictions']} imagination predictions, "
                        f"{counts['test_frames']} AE test frames)")
    for column in ("", "BCE", "IoU", "Dice", "tip error (mm)"):
        table.add_column(column, justify="left" if not column else "right")
    scores_row(table, "autoencoder, test segment", metrics["autoencoder_test"])
    for key, label in ROWS.items():
        scores_row(table, f"{label}, last 5 %", metrics["imagination"][key])
    if "validation" in metrics:
        count = len(metrics["validation"]["recordings"])
        for key, label in ROWS.items():
            scores_row(table, f"{label}, {count} held-out recordings", metrics["validation"][key])
    mse = metrics["latent_mse"]
    table.caption = f"latent MSE (normalised): test {mse['test']:.3f}, imagination {mse['imagine']:.3f}"
    return table


REPLAY_ROWS = {"imagination": "imagination, all predicted frames", "imagination_last_5s": "imagination, last 5 s",
               "imagination_seeing": "imagination, camera seeing", "imagination_blind": "imagination, camera blind",
               "fused": "fused view (camera + imagination)"}


def replay_table(metrics: dict[str, Any]) -> Table:
    """Replay scores: every imagined frame, the last 5 s, blind and seeing frames, the fused view."""
    table = Table(title=f"replay of {metrics['recording']} ({metrics['predicted_frames']} imagined frames, "
                        f"{metrics['blind_frames']} blind)")
    for column in ("", "BCE", "IoU", "Dice", "tip error (mm)"):
        table.add_column(column, justify="left" if not column else "right")
    for key, label in REPLAY_ROWS.items():
        if metrics.get(key) is not None:
            scores_row(table, label, metrics[key])
    trust, felt = metrics["confidence"], metrics.get("surprise") or {}
    table.caption = (f"confidence: mean {trust['mean']:.2f}, Spearman correlation with the frames' IoU "
                     f"{trust['spearman_with_iou']:.2f}" + (f"; surprise: mean {felt['mean']:.2f}, {felt['alarms']} alarms"
                                                             if felt.get("mean") is not None else ""))
    return table


def suite_table(evaluation: dict[str, Any]) -> Table:
    """One row per family: the model's IoU, BCE, tip error and skill, and the baselines' IoU beside them (the
    privileged node ridge too, where the checkpoint has it); the mean of each group of families below."""
    families = evaluation["families"]
    privileged = any("ridge_nodes" in row["baselines"] for row in families.values())
    table = Table(title=f"{evaluation['suite']}: {evaluation['checkpoint']}")
    columns = ["family", "frames", "IoU", "BCE", "tip (mm)", "tip median (mm)", "skill", "mean-frame IoU", "ridge IoU",
               "ridge skill", "AE ceiling IoU", *(["node-ridge IoU"] if privileged else [])]
    for column in columns:
        table.add_column(column, justify="left" if column == "family" else "right")
    for name, row in families.items():
        b = row["baselines"]
        table.add_row(name, str(row["frames"]), f"{row['iou']:.3f}", f"{row['bce']:.4f}", f"{row['tip_error_mm']:.1f}",
                      f"{row['tip_error_median_mm']:.1f}", f"{row['skill']:.2f}", f"{b['mean_frame']['iou']:.3f}",
                      f"{b['ridge']['iou']:.3f}", f"{b['ridge']['skill']:.2f}", f"{b['ae_ceiling']['iou']:.3f}",
                      *([f"{b['ridge_nodes']['iou']:.3f}" if "ridge_nodes" in b else ""] if privileged else []))
    means = {f"mean of {group} families": mean for group, mean in evaluation.get("group_means", {}).items()}
    for label, mean in {**means, "mean of families": evaluation["mean"]}.items():
        table.add_row(label, "", f"{mean['iou']:.3f}", f"{mean['bce']:.4f}", f"{mean['tip_error_mm']:.1f}",
                      f"{mean['tip_error_median_mm']:.1f}", f"{mean['skill']:.2f}", *[""] * (len(columns) - 7))
    table.caption = "\n".join([*(trust_line(evaluation["confidence"], name) for name in evaluation["confidence"]["methods"]),
                                *surprise_lines(evaluation.get("surprise"))])
    return table


def trust_line(report: dict[str, Any], name: str) -> str:
    """One confidence's scores over the suite, each with its calibrated reference in brackets."""
    m, ref = report["methods"][name], report["methods"][name]["reference"]
    chosen = " (the checkpoint's)" if name == report["default"] else ""
    return (f"confidence by {name}{chosen} over {m['frames']} frames: Spearman with IoU {m['spearman']:.2f} "
            f"[{ref['spearman']:.2f}], AUROC for IoU < {report['flagged_below']} {m['auroc']:.2f} [{ref['auroc']:.2f}], "
            f"AUSE {m['ause']:.4f} [{ref['ause']:.4f}]; IoU of the {report['least_trusted_share']:.0%} least trusted "
            f"{m['least_trusted_iou']:.3f}, of the rest {m['rest_iou']:.3f}")


def surprise_lines(report: Optional[dict[str, Any]]) -> list[str]:
    """Per disturbance family: the surprise's AUROC and its alarm's latency at the suite's threshold."""
    if report is None:
        return ["surprise: the checkpoint has no forward model (trained by an older softarm, or reads no stretch)"]
    rate = report["false_alarms_per_minute"]
    return [f"surprise (alarm at {report['thresholds']['suite']:.1f}, {rate['suite']:.2f} false alarms a minute; the "
            f"checkpoint's {report['thresholds']['own']:.1f}, {rate['own']:.2f} a minute): " + "; ".join(
                f"{name} AUROC {row['auroc']:.2f}{touching(row)}, latency {row['latency_ms_suite']:.0f} ms "
                f"({row['detected_suite']:.0%} detected)" for name, row in report["families"].items()),
            "false alarms a minute at the checkpoint's threshold, by undisturbed family: " + ", ".join(
                f"{name} {rate:.1f}" for name, rate in report["false_alarms_per_minute_by_family"].items())]


def touching(row: dict[str, Any]) -> str:
    """Where an obstacle stands (scored against the touches): the AUROC against its whole interval beside them."""
    if "auroc_present" not in row:
        return ""
    return (f" against the touches ({row['auroc_present']:.2f} against the obstacle standing there, touched in "
            f"{row['touching_share']:.0%} of its frames, first {row['first_touch_ms']:.0f} ms after its onset)")
