"""A study's results as files: results.json (every trial's settings and suite scores), results.md (one row
per trial) and <study>.png, written whole after every trial, so a running study can be read at any time."""

import dataclasses
from pathlib import Path
from typing import Any, Optional

from softarm.files import atomic_path, write_json
from softarm.study.ledger import TrialRecord
from softarm.study.plan import Study, format_value


def output_paths(folder: Path, study: Study) -> tuple[Path, Path, Path]:
    """(results.json, results.md, <study>.png) in the study's folder."""
    return folder / "results.json", folder / "results.md", folder / f"{study.name}.png"


def write_results(folder: Path, study: Study, scale: str, records: list[TrialRecord]) -> tuple[Path, Path, Path]:
    """All three outputs for the records of the study's planned trials, in its order."""
    from softarm.study.plot import save_study_png

    json_path, md_path, png_path = output_paths(folder, study)
    write_json(json_path, {"study": study.name, "variable": study.variable, "description": study.description,
                           "scale": scale, "trials": [dataclasses.asdict(r) for r in records]})
    with atomic_path(md_path) as part:
        part.write_text(results_markdown(study, scale, records))
    save_study_png(study, scale, records, png_path)
    return json_path, md_path, png_path


def results_markdown(study: Study, scale: str, records: list[TrialRecord]) -> str:
    """A heading, a count of trials by status, the table and every failure's message."""
    counts = ", ".join(f"{sum(r.status == s for r in records)} {s}" for s in ("ok", "failed", "pending"))
    failures = [f"- {r.name}: {r.error}" for r in records if r.status == "failed"]
    return "\n".join([f"# Study {study.name}: {study.description or study.variable}", "",
                      f"Scale {scale}: {len(records)} trials, {counts}.", "", results_table(study, records),
                      *([""] + failures if failures else [])]) + "\n"


def results_table(study: Study, records: list[TrialRecord]) -> str:
    """One Markdown row per trial: mean IoU, tip error and skill over the suite's families, then each family's IoU."""
    families = next((list(r.scores["families"]) for r in records if r.status == "ok"), [])
    grouped = any(r.group for r in records)
    head = ["trial", *(["group"] if grouped else []), study.variable, "status", "mean IoU", "tip (mm)", "skill",
            *families, "wall (s)"]
    lines = ["| " + " | ".join(head) + " |",
             "|" + "|".join("---" if k < 3 + grouped else "---:" for k in range(len(head))) + "|"]
    for r in records:
        mean = r.scores.get("mean", {})
        cells = [r.name, *([r.group] if grouped else []), format_value(r.value), r.status,
                 _number(mean.get("iou"), 3), _number(mean.get("tip_error_mm"), 1), _number(mean.get("skill"), 2),
                 *(_number(r.scores["families"][f]["iou"], 3) if r.status == "ok" else "" for f in families),
                 _number(r.wall_seconds, 0) if r.status != "pending" else ""]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _number(value: Optional[Any], digits: int) -> str:
    return "" if value is None else f"{value:.{digits}f}"
