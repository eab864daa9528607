"""`--mask auto`: the Otsu rule that separates best, on the side that leaves the arm the smaller class, the colour
cut fitted to its classes (judged on blurred edges against the share of each pixel the arm covers), and masks
cleaned to their main parts; judged on synthetic scenes against the arm drawn into them, and on robot-style logs
of other scenes against the recording they were made from."""

import numpy as np
import pytest

from softarm.errors import ConfigError
from softarm.real.segment import choose_rule, chroma_difference, fit_colour, main_parts, parse_mask


def scene(arm_rgb, wall_rgb, seed: int = 0) -> tuple[list[np.ndarray], np.ndarray]:
    """Four 120x80 frames of a textured wall with a bar-shaped arm hanging from the top (12 % of the pixels)."""
    rng = np.random.default_rng(seed)
    arm = np.zeros((120, 80), bool)
    arm[:100, 35:45] = True
    frames = []
    for _ in range(4):
        wall = np.clip(np.asarray(wall_rgb, float) + rng.normal(0, 12, (120, 80, 1)) + rng.normal(0, 3, (120, 80, 3)),
                       0, 255)
        frames.append(np.where(arm[..., None], arm_rgb, wall).astype(np.uint8))
    return frames, arm


@pytest.mark.parametrize("arm_rgb, wall_rgb", [((215, 95, 35), (98, 128, 126)), ((40, 35, 45), (200, 200, 190)),
                                               ((230, 225, 200), (60, 70, 80)), ((30, 160, 40), (140, 140, 140))])
def test_auto_finds_the_arm_whatever_its_colour_against_the_wall(arm_rgb, wall_rgb):
    frames, arm = scene(arm_rgb, wall_rgb)
    rule, threshold, score = choose_rule(frames, None)
    found = rule.apply(rule.channel(frames[0], None), threshold)
    assert (found & arm).sum() / (found | arm).sum() > 0.98 and score > 0.8, (rule.text, score)


def blurred_scene(arm_rgb, wall_rgb, seed: int = 0) -> tuple[list[np.ndarray], np.ndarray]:
    """Four frames of a textured wall and a tapering arm whose edges are blurred: each pixel the wall's and the
    arm's colour mixed in the share of it the arm covers (a camera's blur or a smeared exposure), returned with
    that share, the reference any rule's mask is judged against (a pixel is arm where it is covered at least half)."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:120, 0:80].astype(float)
    half_width = 9.0 - 7.0 * yy / 120  # wide at the base, thin at the tip
    cover = np.clip((half_width - np.abs(xx - 40)) / 4.0 + 0.5, 0, 1) * (yy < 110)  # edges 4 px wide
    frames = []
    for _ in range(4):
        wall = (np.asarray(wall_rgb, float) + rng.normal(0, 6, (120, 80, 1)) + rng.normal(0, 3, (120, 80, 3))
                + 20 * np.sin(xx / 7)[..., None])
        mixed = cover[..., None] * np.asarray(arm_rgb, float) + (1 - cover[..., None]) * wall
        frames.append(np.clip(np.rint(mixed), 0, 255).astype(np.uint8))
    return frames, cover


@pytest.mark.parametrize("arm_rgb, wall_rgb", [((215, 95, 35), (98, 128, 126)), ((40, 35, 45), (200, 200, 190))])
def test_the_colour_cut_keeps_the_pixels_the_arm_covers_at_least_half_of(arm_rgb, wall_rgb):
    frames, cover = blurred_scene(arm_rgb, wall_rgb)
    seed, threshold, _ = choose_rule(frames, None)
    colour = fit_colour(frames, seed, threshold)
    assert colour is not None and colour.seed == seed.text
    truth = cover >= 0.5

    def iou(found: np.ndarray) -> float:
        return float((found & truth).sum() / (found | truth).sum())
    by_colour = [iou(colour.apply(colour.channel(f, None), None)) for f in frames]
    by_seed = [iou(seed.apply(seed.channel(f, None), threshold)) for f in frames]
    assert min(by_colour) > 0.95 and np.mean(by_colour) > np.mean(by_seed) + 0.005, (seed.text, by_colour, by_seed)


def test_the_colour_cut_prints_as_a_rule_that_parses_back_to_the_same_masks():
    frames, _ = blurred_scene((215, 95, 35), (98, 128, 126))
    colour = fit_colour(frames, *choose_rule(frames, None)[:2])
    again = parse_mask(colour.text)
    assert again.weights == colour.weights and again.cut == colour.cut
    assert np.array_equal(again.apply(again.channel(frames[1], None), None),
                          colour.apply(colour.channel(frames[1], None), None))
    with pytest.raises(ConfigError, match="all zero"):
        parse_mask("rgb=0,0,0>10")
    with pytest.raises(ConfigError, match="rgb=WR,WG,WB>CUT"):
        parse_mask("rgb=1,2>10")


def test_no_colour_cut_is_fitted_where_the_rule_finds_a_single_class():
    flat = [np.full((40, 40, 3), 120, np.uint8) for _ in range(2)]
    from softarm.real.segment import Threshold

    assert fit_colour(flat, Threshold("s>otsu", "s", True, None), 10.0) is None


def test_a_scene_with_no_arm_to_separate_scores_below_the_warning():
    from softarm.real.segment import SEPARABLE

    noise = [np.clip(np.random.default_rng(k).normal(128, 30, (120, 80, 3)), 0, 255).astype(np.uint8) for k in range(4)]
    assert choose_rule(noise, None)[2] < SEPARABLE


def test_main_parts_keep_the_arm_and_its_cut_off_tip_not_specks_or_a_small_object():
    mask = np.zeros((84, 52), np.uint8)
    mask[0:60, 24:28] = 1          # the arm, 240 pixels
    mask[63:80, 24:28] = 1         # its tip, cut off by downsampling: 68 pixels, over a quarter of the arm
    mask[40:44, 40:44] = 1         # an object apart, 16 pixels
    mask[5, 45] = 1                # a speck
    kept = main_parts(mask)
    expected = np.zeros_like(mask)
    expected[0:60, 24:28] = 1
    expected[63:80, 24:28] = 1
    assert np.array_equal(kept, expected) and kept.dtype == mask.dtype
    assert np.array_equal(main_parts(np.zeros_like(mask)), np.zeros_like(mask))


def test_chromaticity_does_not_see_the_light_change_only_the_colour():
    rng = np.random.default_rng(1)
    wall = rng.integers(60, 200, (30, 30, 3)).astype(np.int16)
    dimmer = np.rint(wall * 0.7).astype(np.uint8)
    assert chroma_difference(dimmer, wall).max() < 8            # the same colours, less light
    arm = wall.astype(np.uint8).copy()
    arm[10:20, 10:20] = (215, 95, 35)
    assert chroma_difference(arm, wall)[10:20, 10:20].min() > 40 and chroma_difference(arm, wall)[0].max() == 0


SCENES = {"dark arm, light wall": ["--arm-colour", "40,35,45", "--scene-colour", "200,200,190"],
          "pale arm, dark wall": ["--arm-colour", "230,225,200", "--scene-colour", "60,70,80"],
          "light that drifts, a swinging object": ["--lighting-drift", "0.3", "--distractor"]}


@pytest.mark.slow
@pytest.mark.parametrize("scene_name", list(SCENES))
def test_auto_masks_of_other_scenes_match_the_recordings_frames(recordings, tmp_path, scene_name):
    from softarm.model.metrics import iou_per_frame
    from softarm.record.reader import read_recording
    from tests.helpers.cli import softarm

    done = softarm("robot-log", str(recordings / "s0.mcap"), "--out", "log.mcap", *SCENES[scene_name], cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    done = softarm("import", "log.mcap", "--camera", "/camera/image_raw/compressed", "--sensors", "/arm/stretch:data",
                   "--roi", "190,30,260,420", "--out", "imported.mcap", cwd=tmp_path)
    assert done.returncode == 0 and "auto chose" in done.stdout, done.stdout + done.stderr
    native, rec = read_recording(recordings / "s0.mcap"), read_recording(tmp_path / "imported.mcap")
    found = rec.model["source"]["found"]
    assert found["rule"].startswith("rgb=") and found["auto_rule"].endswith("otsu") and found["rule"] in done.stdout
    k = np.rint((rec.model["source"]["found"]["t0"] - 1_700_000_000.0 + rec.times) / native.frame_dt).astype(int)
    seen = rec.seen & (k < len(native.times))
    assert iou_per_frame(rec.frames[seen].astype(float), native.frames[k[seen]]).mean() > 0.95


def test_the_run_spreading_fill_reaches_what_a_breadth_first_search_reaches():
    from collections import deque

    from softarm.real.segment import _grow

    def search(seeds: np.ndarray, inside: np.ndarray) -> np.ndarray:
        out, queue = seeds & inside, deque(zip(*np.nonzero(seeds & inside)))
        while queue:
            y, x = queue.popleft()
            for v, u in ((y + 1, x), (y - 1, x), (y, x + 1), (y, x - 1)):
                if 0 <= v < inside.shape[0] and 0 <= u < inside.shape[1] and inside[v, u] and not out[v, u]:
                    out[v, u] = True
                    queue.append((v, u))
        return out

    rng = np.random.default_rng(0)
    for _ in range(200):  # random masks around the percolation threshold: long, winding parts
        inside = rng.random((30, 20)) < rng.uniform(0.3, 0.7)
        seeds = (rng.random((30, 20)) < 0.02) & inside
        assert np.array_equal(_grow(seeds, inside), search(seeds, inside))
