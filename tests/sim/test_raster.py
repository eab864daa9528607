"""The Taichi rasteriser against a NumPy even-odd ray cast from every pixel centre and against cv2.fillPoly.

The ray cast is the definition in docs/model.md (Camera) written out directly: a pixel is 1 when a ray
from its centre (c + 0.5, r + 0.5) crosses the outline an odd number of times. It must agree pixel
for pixel, except ties: centres within 1e-9 px of the outline, where the answer depends on rounding
and on a tie rule that docs/model.md leaves open (the rule the scanline follows is pinned in
`test_pixel_centres_on_the_outline_go_to_left_and_top_edges`). cv2.fillPoly is a second, foreign
rasteriser with its own edge rule, so it may differ only next to the outline.
"""

import cv2
import numpy as np
import pytest
import taichi as ti

from softarm.arm.camera import world_to_pixel
from softarm.config import CameraConfig, load_config
from softarm.sim.batch import arm_batch
from softarm.sim.physics import Simulator
from softarm.sim.raster import Rasteriser

CAMERA = load_config().camera                                                        # 84 x 52, 400 px/m
UNIT = CameraConfig(width=20, height=16, pixels_per_metre=1.0, origin=(0.0, 0.0))  # u = x, v = -y, exact
TIE = 1e-9  # px: a centre this close to the outline is a tie


# ---- independent references ----------------------------------------------------------------------

def to_pixels(camera: CameraConfig, points: np.ndarray) -> np.ndarray:
    """(..., 2) world points -> (..., 2) pixel points [u, v]."""
    M = world_to_pixel(camera)
    return points @ M[:, :2].T + M[:, 2]


def pixel_centres(camera: CameraConfig) -> np.ndarray:
    """(H, W, 2) centres [c + 0.5, r + 0.5] of every pixel."""
    v, u = np.mgrid[0:camera.height, 0:camera.width] + 0.5
    return np.stack([u, v], axis=-1)


def ray_cast(polygon: np.ndarray, camera: CameraConfig) -> np.ndarray:
    """(H, W) uint8: 1 where a ray from the pixel centre towards +u crosses the closed polygon an odd number of times.

    An edge p -> q counts when it straddles the centre's line (half-open in v, so a vertex on the line
    is counted once) and crosses it right of the centre: the crossing lies at u_c + cross / (q_v - p_v),
    with cross = (q - p) x (centre - p), so no division is needed.
    """
    c = pixel_centres(camera)[:, :, None, :]
    p, q = polygon, np.roll(polygon, -1, axis=0)
    straddles = (p[:, 1] > c[..., 1]) != (q[:, 1] > c[..., 1])
    cross = (q[:, 0] - p[:, 0]) * (c[..., 1] - p[:, 1]) - (q[:, 1] - p[:, 1]) * (c[..., 0] - p[:, 0])
    crossings = np.count_nonzero(straddles & (cross * (q[:, 1] - p[:, 1]) > 0), axis=-1)
    return (crossings % 2).astype(np.uint8)


def distance_to_outline(polygon: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(K,) Chebyshev (L-infinity) distance in px from each of (K, 2) points to the closed polygon's edges.

    Below 1 the outline passes through the 3 x 3 pixels around a pixel centre: "next to the outline".
    Along an edge p + t (q - p) the distance max(|a_u + t d_u|, |a_v + t d_v|) is convex and piecewise
    linear in t, so its minimum lies at t = 0, t = 1 or a kink: where a term is 0 or the two are equal.
    """
    a = polygon[None] - points[:, None]                        # (K, E, 2) from the point to each vertex
    d = np.roll(polygon, -1, axis=0) - polygon                 # (E, 2)
    ts = [np.zeros(a.shape[:2]), np.ones(a.shape[:2])]
    for num, den in ((a[..., 0], d[:, 0]), (a[..., 1], d[:, 1]),
                     (a[..., 0] - a[..., 1], d[:, 0] - d[:, 1]), (a[..., 0] + a[..., 1], d[:, 0] + d[:, 1])):
        ts.append(np.clip(-num / np.where(den != 0, den, np.inf), 0.0, 1.0))
    t = np.stack(ts, axis=-1)[..., None]                       # (K, E, 6, 1)
    return np.abs(a[:, :, None] + t * d[None, :, None]).max(axis=-1).min(axis=(1, 2))


def cv2_fill(polygon: np.ndarray, camera: CameraConfig, shift: int = 8) -> np.ndarray:
    """(H, W) uint8 from cv2.fillPoly, whose integer coordinates are pixel centres: (u, v) -> (u - 0.5, v - 0.5).

    fillPoly runs on a canvas that holds the whole polygon, cropped afterwards: where it clips a
    polygon at the image border itself, it fills pixels along the border that lie outside (seen at
    column 0 for polygons reaching u = -11).
    """
    lo = np.minimum(np.floor(polygon.min(axis=0)) - 2, 0).astype(int)  # (u, v) of the canvas origin
    hi = np.maximum(np.ceil(polygon.max(axis=0)) + 2, [camera.width, camera.height]).astype(int)
    canvas = np.zeros((hi[1] - lo[1], hi[0] - lo[0]), np.uint8)
    fixed = np.round((polygon - lo - 0.5) * (1 << shift)).astype(np.int32)
    cv2.fillPoly(canvas, [fixed], 1, lineType=cv2.LINE_8, shift=shift)
    return canvas[-lo[1]:-lo[1] + camera.height, -lo[0]:-lo[0] + camera.width]


# ---- shapes ---------------------------------------------------------------------------------------

def render(camera: CameraConfig, outline: np.ndarray, history: np.ndarray) -> np.ndarray:
    """All frames of an (arms, frames, N, 2) history in one call."""
    arms, frames = history.shape[:2]
    return Rasteriser(camera, outline, arms, frames).render(np.ascontiguousarray(history, np.float64), frames)


def pixel_to_world(camera: CameraConfig, uv: np.ndarray) -> np.ndarray:
    """Inverse of the camera map for (..., 2) pixel coordinates [u, v] -> world [x, y] in metres."""
    M = world_to_pixel(camera)
    return (np.asarray(uv, float) - M[:, 2]) @ np.linalg.inv(M[:, :2]).T


def as_history(pixel_polygons: np.ndarray, camera: CameraConfig) -> np.ndarray:
    """(B, V, 2) pixel-space polygons as a one-arm history whose nodes are their vertices (outline arange(V))."""
    return pixel_to_world(camera, pixel_polygons)[None]


def random_polygons(kind: str, n: int, rng: np.random.Generator, camera: CameraConfig = CAMERA) -> np.ndarray:
    """(n, V, 2) pixel-space polygons of one kind."""
    W, H = camera.width, camera.height
    if kind == "self-intersecting":  # vertices anywhere, frame margin included
        return rng.uniform([-10, -10], [W + 10, H + 10], (n, 13, 2))
    if kind == "on the pixel grid":  # vertices on pixel centres and pixel corners: ties everywhere
        return rng.integers(-2, [W + 2, H + 2], (n, 9, 2)) + rng.choice([0.0, 0.5], (n, 9, 1))
    # star-shaped around a centre: simple, concave in general
    V = 17
    angles = np.sort(rng.uniform(0, 2 * np.pi, (n, V)), axis=1)
    if kind == "simple concave":
        centre, radii = rng.uniform([8, 8], [W - 8, H - 8], (n, 1, 2)), rng.uniform(2, 25, (n, V))
    elif kind == "partly outside the frame":
        centre, radii = rng.uniform([-5, -5], [W + 5, H + 5], (n, 1, 2)), rng.uniform(5, 45, (n, V))
    elif kind == "sub-pixel":
        centre, radii = rng.uniform([0, 0], [W, H], (n, 1, 2)), rng.uniform(0.05, 1.5, (n, V))
    else:
        raise ValueError(kind)
    return centre + radii[..., None] * np.stack([np.cos(angles), np.sin(angles)], axis=-1)


RANDOM_KINDS = ["simple concave", "self-intersecting", "partly outside the frame", "sub-pixel", "on the pixel grid"]


def curled(rest: np.ndarray, angle: float) -> np.ndarray:
    """The rest layout bent along a circle so that the tip turns by `angle` (rad, > 0 curls to +x).

    A node at depth s = -y and offset w = x from the centreline goes to centre(s) + w n(s), with the
    centreline turning at constant curvature; past about 360 degrees the tip runs over the top and
    the outline crosses itself (6 of the fixture's 60 curls), so even-odd leaves holes where it overlaps.
    """
    s, w = -rest[:, 1], rest[:, 0]
    k = angle / s.max()
    phi = k * s
    centre = np.stack([(1 - np.cos(phi)) / k, -np.sin(phi) / k], axis=1)
    return centre + w[:, None] * np.stack([np.cos(phi), np.sin(phi)], axis=1)


@pytest.fixture(scope="module")
def arm_frames():
    """(body, history): 4 arms x 60 frames. Arms 0-2: every 5th frame of 3 s of default runs (seeds 0-2)
    started as a real run starts them; arm 3: the arm curled from -400 to +400 degrees."""
    config = load_config()
    batch = arm_batch(config, seeds=range(3))
    body = batch.body
    swinging = Simulator.from_config(config, batch).advance(300)[:, ::5]
    bent = np.stack([curled(body.rest, a) for a in np.radians(np.linspace(-400, 400, 60))])
    return body, np.concatenate([swinging, bent[None]])


def assert_matches_ray_cast(images: np.ndarray, polygons: np.ndarray, camera: CameraConfig) -> int:
    """Every pixel of every (frame, polygon) pair agrees with the ray cast, ties aside; returns the differing ties."""
    ties = 0
    for k, (image, polygon) in enumerate(zip(images, polygons)):
        differ = np.argwhere(image != ray_cast(polygon, camera))
        tie = distance_to_outline(polygon, differ[:, ::-1] + 0.5) < TIE
        ties += np.count_nonzero(tie)
        assert tie.all(), (f"frame {k}: {np.count_nonzero(~tie)} pixels differ from the ray cast, first at "
                           f"(row, col) = {differ[~tie][0].tolist()}; polygon (u, v) = {polygon.tolist()}")
    return ties


# ---- the ray cast itself --------------------------------------------------------------------------

def test_ray_cast_reference_fills_a_rectangle_and_a_triangle_by_their_half_planes():
    c = pixel_centres(UNIT)
    u, v = c[..., 0], c[..., 1]
    rectangle = np.array([[2.3, 3.1], [11.8, 3.1], [11.8, 9.6], [2.3, 9.6]])
    assert np.array_equal(ray_cast(rectangle, UNIT), ((u > 2.3) & (u < 11.8) & (v > 3.1) & (v < 9.6)).astype(np.uint8))
    triangle = np.array([[1.2, 1.1], [18.7, 2.3], [4.4, 14.9]])  # clockwise on screen (v down)
    p, q = triangle, np.roll(triangle, -1, axis=0)
    sides = (q[:, 0] - p[:, 0]) * (v[..., None] - p[:, 1]) - (q[:, 1] - p[:, 1]) * (u[..., None] - p[:, 0])
    assert np.array_equal(ray_cast(triangle, UNIT), np.all(sides > 0, axis=-1).astype(np.uint8))


# ---- Taichi against the ray cast -----------------------------------------------------------------

@pytest.mark.slow
def test_arm_frames_match_an_even_odd_ray_cast_from_every_pixel_centre(arm_frames):
    body, history = arm_frames
    images = render(CAMERA, body.outline, history)
    polygons = to_pixels(CAMERA, history[:, :, body.outline])
    differing_ties = sum(assert_matches_ray_cast(images[a], polygons[a], CAMERA) for a in range(len(history)))
    assert differing_ties == 0  # measured: no centre lies on an arm outline (the top edge is on v = 3.0)
    assert images.sum(axis=(2, 3)).min() > 300  # the arm is seen in every frame


def render_random(kind: str) -> tuple[CameraConfig, np.ndarray, np.ndarray]:
    """(camera, pixel polygons as the rasteriser sees them, images) of 60 random polygons of one kind."""
    camera = UNIT if kind == "on the pixel grid" else CAMERA  # UNIT keeps grid vertices exact through M
    pixels = random_polygons(kind, 60, np.random.default_rng(RANDOM_KINDS.index(kind)), camera)
    history = as_history(pixels, camera)
    return camera, to_pixels(camera, history[0]), render(camera, np.arange(pixels.shape[1]), history)[0]


@pytest.mark.parametrize("kind", RANDOM_KINDS)
def test_random_polygons_match_an_even_odd_ray_cast_from_every_pixel_centre(kind):
    camera, polygons, images = render_random(kind)
    differing_ties = assert_matches_ray_cast(images, polygons, camera)
    assert differing_ties == 0  # measured: none, the ray cast settles ties as the scanline does
    if kind == "on the pixel grid":
        centres = pixel_centres(camera).reshape(-1, 2)
        ties = sum(np.count_nonzero(distance_to_outline(p, centres) < TIE) for p in polygons)
        assert ties > 100  # measured: 509 centres on an outline, over 60 polygons
    assert images.any(axis=(1, 2)).sum() > (10 if kind == "sub-pixel" else 40)


def test_pixel_centres_on_the_outline_go_to_left_and_top_edges():
    # Ties, as the scanline settles them: a crossing counts only strictly right of a centre (u_c < u),
    # and an edge counts for a centre line v_c when one end has v > v_c and the other v <= v_c. So a
    # centre on a left edge or on a top (smaller v) horizontal edge is 1; on a right or bottom edge 0.
    # This is the usual top-left fill rule: polygons that share an edge never both own its pixels.
    # Rectangle with every vertex on a pixel centre: (3.5, 2.5) .. (9.5, 7.5), i.e. columns 3..9, rows 2..7.
    rectangle = np.array([[3.5, 2.5], [9.5, 2.5], [9.5, 7.5], [3.5, 7.5]])
    image = render(UNIT, np.arange(4), as_history(rectangle[None], UNIT))[0, 0]
    expected = np.zeros((UNIT.height, UNIT.width), np.uint8)
    expected[2:7, 3:9] = 1  # top row 2 and left column 3 in; bottom row 7 and right column 9 out
    assert np.array_equal(image, expected)
    reversed_winding = render(UNIT, np.arange(4), as_history(rectangle[None, ::-1], UNIT))[0, 0]
    assert np.array_equal(reversed_winding, image)


def test_polygons_sharing_edges_own_each_pixel_centre_on_them_exactly_once():
    # A fan of triangles around a centre on a pixel centre, with spokes through pixel centres: every
    # centre of the covered square belongs to exactly one triangle, ties on spokes included.
    centre, ring = np.array([10.5, 8.5]), np.array([[4.5, 2.5], [16.5, 2.5], [16.5, 14.5], [4.5, 14.5]])
    corners = np.concatenate([ring, [[10.5, 2.5], [16.5, 8.5], [10.5, 14.5], [4.5, 8.5]]])
    corners = corners[np.argsort(np.arctan2(*(corners - centre).T[::-1]))]
    fan = np.stack([[centre, a, b] for a, b in zip(corners, np.roll(corners, -1, axis=0))])
    images = render(UNIT, np.arange(3), as_history(fan, UNIT))[0]
    square = render(UNIT, np.arange(4), as_history(ring[None], UNIT))[0, 0]
    assert images.sum(axis=0).max() == 1
    assert np.array_equal(images.sum(axis=0), square)


# ---- Taichi against cv2.fillPoly ------------------------------------------------------------------

def assert_agrees_with_cv2_next_to_the_outline(images: np.ndarray, polygons: np.ndarray, camera: CameraConfig):
    """Every pixel where Taichi and cv2.fillPoly differ has its centre within 1 px of the outline; returns
    (differing pixels, pixels that are 1 in either image)."""
    differing = covered = 0
    for k, (image, polygon) in enumerate(zip(images, polygons)):
        theirs = cv2_fill(polygon, camera)
        wrong = np.argwhere(image != theirs)
        far = wrong[distance_to_outline(polygon, wrong[:, ::-1] + 0.5) >= 1.0]
        assert len(far) == 0, (f"polygon {k}: pixels (row, col) {far[:5].tolist()} differ from cv2.fillPoly "
                               f"more than 1 px from the outline {polygon.tolist()}")
        differing += len(wrong)
        covered += np.count_nonzero(image | theirs)
    return differing, covered


def test_arm_frames_agree_with_cv2_fillpoly_except_next_to_the_outline(arm_frames):
    body, history = arm_frames
    images = render(CAMERA, body.outline, history)
    polygons = to_pixels(CAMERA, history[:, :, body.outline])
    differing, covered = np.sum([assert_agrees_with_cv2_next_to_the_outline(images[a], polygons[a], CAMERA)
                                 for a in range(len(history))], axis=0)
    # Measured: 16,654 of 144,074 covered pixels differ (11.6%; 1.6% of all pixels) over 240 frames,
    # all within 0.81 px (L-inf) of the outline, and all but 2 are 1 in cv2 only: fillPoly also sets
    # the pixels its edges pass through, the centre rule only those whose centre is inside.
    assert differing / covered < 0.15, f"{differing} of {covered} covered pixels differ from cv2.fillPoly"


# Share of covered pixels (1 in either image) where cv2.fillPoly differs, measured on the 60 polygons
# of each kind; nearly all are 1 in cv2 only. Sub-pixel polygons are mostly outline.
CV2_DIFFERS = {"simple concave": 0.134, "self-intersecting": 0.123, "partly outside the frame": 0.063,
               "sub-pixel": 0.753, "on the pixel grid": 0.318}


@pytest.mark.parametrize("kind", RANDOM_KINDS)
def test_random_polygons_agree_with_cv2_fillpoly_except_next_to_the_outline(kind):
    camera, polygons, images = render_random(kind)
    differing, covered = assert_agrees_with_cv2_next_to_the_outline(images, polygons, camera)
    assert differing / covered < min(1.5 * CV2_DIFFERS[kind], 1.0), \
        f"{kind}: {differing} of {covered} covered pixels differ from cv2.fillPoly"


# ---- batches and output ---------------------------------------------------------------------------

def test_a_batch_of_arms_and_frames_renders_as_each_frame_alone(arm_frames):
    body, history = arm_frames
    batch = history[:, ::7]  # 4 arms x 9 frames, hanging, swinging and curled
    images = render(CAMERA, body.outline, batch)
    single = Rasteriser(CAMERA, body.outline, 1, 1)
    for a in range(batch.shape[0]):
        for f in range(batch.shape[1]):
            assert np.array_equal(images[a, f], single.render(np.ascontiguousarray(batch[a:a + 1, f:f + 1]), 1)[0, 0])
    assert len({images[a, f].tobytes() for a in range(batch.shape[0]) for f in range(batch.shape[1])}) > 20


def test_history_as_a_taichi_ndarray_renders_as_the_numpy_array(arm_frames):
    body, history = arm_frames
    nd = ti.ndarray(ti.f64, history.shape)
    nd.from_numpy(np.ascontiguousarray(history))
    rasteriser = Rasteriser(CAMERA, body.outline, *history.shape[:2])
    assert np.array_equal(rasteriser.render(nd, history.shape[1]), rasteriser.render(history, history.shape[1]))


def test_frames_are_0_or_1_uint8_of_shape_arms_frames_height_width(arm_frames):
    body, history = arm_frames
    images = Rasteriser(CAMERA, body.outline, 4, 50).render(np.ascontiguousarray(history[:, :50]), 7)
    assert images.dtype == np.uint8 and images.shape == (4, 7, CAMERA.height, CAMERA.width)
    assert set(np.unique(images)) == {0, 1}


def test_frames_beyond_n_frames_are_neither_read_nor_returned(arm_frames):
    body, history = arm_frames
    rasteriser = Rasteriser(CAMERA, body.outline, 4, 10)
    rasteriser.render(np.ascontiguousarray(history[:, 40:50]), 10)  # leaves ten other frames in the block
    later = history[:, :10].copy()
    later[:, 3:] = np.nan  # never looked at
    images = rasteriser.render(later, 3)
    assert images.shape == (4, 3, CAMERA.height, CAMERA.width)
    assert np.array_equal(images, render(CAMERA, body.outline, history[:, :3]))


def test_an_edge_far_right_of_the_frame_still_closes_the_polygon():
    # Rows 1..2, u from 2 to 1e10 px: columns 2.. are inside. Unreachable for an arm (blow-up stops
    # a run 0.5 m = 200 px from rest), so this only pins the clamp order.
    band = np.array([[2.0, 1.0], [1e10, 1.0], [1e10, 3.0], [2.0, 3.0]])
    image = render(UNIT, np.arange(4), as_history(band[None], UNIT))[0, 0]
    assert np.array_equal(image, ray_cast(band, UNIT))
