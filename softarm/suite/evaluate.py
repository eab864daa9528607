"""`softarm evaluate` as one call: check the outputs, evaluate the checkpoint on the suite, write JSON and PNG."""

from pathlib import Path
from typing import Any, Optional, Union

from softarm.errors import CheckpointError
from softarm.files import check_outputs, claimed, input_file, made_folders, write_json
from softarm.suite.manifest import MANIFEST, read_suite
from softarm.suite.scoring import Progress, evaluate_suite
from softarm.trust.scoring import FRACTIONS

PathLike = Union[str, Path]


def evaluate(checkpoint: PathLike, suite: PathLike, json_path: Optional[PathLike] = None,
             png: Optional[PathLike] = None, sensor_noise: Optional[dict[str, Any]] = None, force: bool = False,
             progress: Optional[Progress] = None, trust_png: Optional[PathLike] = None,
             device: str = "auto") -> dict[str, Any]:
    """Score `checkpoint` on every family of the suite in `suite` (see softarm.suite.scoring), its networks on
    `device`; write the document as JSON, the bars as PNG and the confidences' sparsification curves as PNG where
    asked. Outputs are checked before any work."""
    outputs = [Path(p) for p in (json_path, png, trust_png) if p is not None]
    cases = read_suite(suite).cases  # a missing or damaged suite is refused before any work
    check_outputs(outputs, force, inputs=[checkpoint, Path(suite) / MANIFEST, *(case.path for case in cases)])
    input_file(checkpoint, "checkpoint", CheckpointError)  # before torch loads
    with made_folders(outputs), claimed(outputs):
        evaluation = evaluate_suite(checkpoint, suite, sensor_noise=sensor_noise, progress=progress, device=device)
        if json_path is not None:
            write_json(json_path, evaluation)
        if png is not None:
            from softarm.view.suite_plot import save_suite_png

            save_suite_png(evaluation, png)
        if trust_png is not None:
            from softarm.trust.plot import save_sparsification_png

            save_sparsification_png(evaluation["confidence"], trust_png, FRACTIONS, evaluation["checkpoint"])
    return evaluation
