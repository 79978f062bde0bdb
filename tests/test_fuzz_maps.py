"""Fuzzing map files: images of every size and mode (1 x 1, all wall, all free), truncated PNGs,
headers claiming huge images, bytes that are no image, odd .npy arrays. The loader and every
model that takes a map file must give an arena / a run, or raise the project's error naming
the file or the parameter.
"""

import io
import struct
import zlib

import numpy as np
import pytest
from fuzzing import case, examples, memory_ceiling
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from PIL import Image

from abm.arena import MAX_MAP_PIXELS, Arena
from abm.errors import ConfigError, MapError
from abm.registry import model_class

#: Simulated time each accepted model case runs (s).
SHORT = 2.0
#: Model -> the parameter that takes a map file.
MAP_PARAMS = {"beacon-explorer": "world", "stigmergy": "map", "sugarmap": "arena",
              "hierarchy": "world"}  # fmt: skip
MODES = ["1", "L", "P", "RGB", "RGBA", "I;16", "LA"]


def png_bytes(free: np.ndarray, mode: str, fmt: str) -> bytes:
    """``free`` drawn white (free) on black, saved in image ``mode`` and format ``fmt``."""
    image = Image.fromarray(np.where(free, 255, 0).astype(np.uint8), mode="L").convert(mode)
    writable = {"PPM": ("1", "L", "RGB"), "BMP": ("1", "L", "P", "RGB")}.get(fmt, MODES)
    if mode not in writable:
        image = image.convert("RGB" if fmt == "BMP" else "L")
    buffer = io.BytesIO()
    image.save(buffer, format=fmt)
    return buffer.getvalue()


def alpha_png(free: np.ndarray, alpha: np.ndarray) -> bytes:
    """``free`` drawn white on black with the transparency ``alpha`` (0 = clear), as RGBA."""
    grey = np.where(free, 255, 0).astype(np.uint8)
    rgba = np.dstack([grey, grey, grey, np.resize(alpha, free.shape).astype(np.uint8)])
    buffer = io.BytesIO()
    Image.fromarray(rgba, mode="RGBA").save(buffer, format="PNG")
    return buffer.getvalue()


def huge_png(width: int, height: int) -> bytes:
    """A PNG whose header claims ``width`` x ``height`` pixels (its data is one tiny row)."""
    header = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)

    def chunk(kind: bytes, data: bytes) -> bytes:
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
            + chunk(b"IDAT", zlib.compress(b"\x00\xff")) + chunk(b"IEND", b""))  # fmt: skip


def npy_bytes(array: np.ndarray) -> bytes:
    buffer = io.BytesIO()
    np.save(buffer, array, allow_pickle=False)
    return buffer.getvalue()


def hall(rows: int, cols: int, seed: int, density: float) -> np.ndarray:
    """A walled hall with a random ``density`` of wall pixels inside (a map a model can run)."""
    free = np.random.default_rng(seed).random((rows, cols)) >= density
    free[[0, -1], :] = free[:, [0, -1]] = False
    return free


GRIDS = st.one_of(
    st.builds(
        hall,
        st.integers(3, 110),
        st.integers(3, 110),
        st.integers(0, 2**32 - 1),
        st.sampled_from([0.0, 0.01, 0.1, 0.5]),
    ),  # fmt: skip
    hnp.arrays(bool, st.tuples(st.integers(1, 40), st.integers(1, 40))),
    st.tuples(st.integers(1, 40), st.integers(1, 40), st.booleans()).map(
        lambda t: np.full(t[:2], t[2])
    ),  # all free or all wall
    st.sampled_from([np.ones((1, 1), bool), np.zeros((1, 1), bool), np.ones((1, 300), bool)]),
)
IMAGES = st.builds(png_bytes, GRIDS, st.sampled_from(MODES), st.sampled_from(["PNG", "BMP"]))
FILES = st.one_of(
    st.tuples(IMAGES, st.just(".png")),
    st.tuples(st.builds(png_bytes, GRIDS, st.sampled_from(["L", "1"]), st.just("PPM")),
              st.just(".pgm")),
    st.tuples(st.builds(lambda b, k: b[: k % max(len(b), 1)], IMAGES, st.integers(0, 10**4)),
              st.just(".png")),  # truncated
    st.tuples(st.binary(max_size=200), st.sampled_from([".png", ".bmp", ".pgm", ".npy"])),
    st.tuples(st.builds(huge_png, st.integers(1, 2**31 - 1), st.integers(1, 2**31 - 1)),
              st.just(".png")),
    st.tuples(st.builds(npy_bytes, hnp.arrays(
        st.sampled_from([bool, np.int8, np.float64, np.complex64, np.uint16]),
        hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=30))), st.just(".npy")),
    st.tuples(st.builds(lambda b, k: b[: k % max(len(b), 1)],
                        st.builds(npy_bytes, hnp.arrays(bool, (20, 20))), st.integers(0, 500)),
              st.just(".npy")),  # truncated
    st.tuples(st.builds(alpha_png, GRIDS, st.one_of(
        st.sampled_from([np.zeros(1), np.full(1, 255), np.array([0, 255]), np.array([127, 128])]),
        hnp.arrays(np.uint8, st.integers(1, 50)))), st.just(".png")),  # transparency
    st.tuples(st.builds(npy_bytes, hnp.arrays(np.float64, st.tuples(
        st.integers(1, 30), st.integers(1, 30)), elements=st.sampled_from(
            [0.0, 1.0, np.nan, np.inf, -np.inf, -0.0])
    )), st.just(".npy")),  # NaN and infinities
)  # fmt: skip


#: Files for the models: the fuzzed ones, and walled halls large enough for every model's
#: default start (so a third of the cases reach a run).
HALLS = st.builds(hall, st.integers(85, 110), st.integers(85, 110), st.integers(0, 2**32 - 1),
                  st.sampled_from([0.0, 0.01, 0.05]))  # fmt: skip
MODEL_FILES = st.one_of(FILES, st.tuples(st.builds(png_bytes, HALLS, st.just("L"), st.just("PNG")),
                                         st.just(".png")))  # fmt: skip


@pytest.fixture(scope="module", autouse=True)
def _ceiling():
    with memory_ceiling():
        yield


def _write(folder, data: bytes, suffix: str):
    path = folder / f"fuzzed{suffix}"
    path.write_bytes(data)
    return path


@examples(250)
@given(file=FILES, linked=st.booleans())
def test_fuzzed_map_files_load_or_raise_map_error_naming_the_file(tmp_path_factory, file, linked):
    path = _write(tmp_path_factory.mktemp("map"), *file)
    if linked:  # the map is a symbolic link to the file, under another name
        link = path.with_name(f"link{path.suffix}")
        link.symlink_to(path.with_name(f"fuzzed{path.suffix}"))
        path = link
    with case("map-file:Arena.from_bitmap", [str(path)]):
        arena = Arena.from_bitmap(path)
        assert arena.free.any() and arena.free.size <= MAX_MAP_PIXELS


@examples(60)
@given(
    rows=st.integers(1, 20_000),
    cols=st.integers(1, 20_000),
    budget=st.integers(1, 2**28),
    suffix=st.sampled_from([".png", ".npy"]),
)
def test_a_map_beyond_the_memory_budget_is_refused_before_decoding(
    tmp_path_factory, rows, cols, budget, suffix
):
    """Any header size against any budget: the loader decodes the map only when the arena's
    estimate fits (and then the map loads); else a MapError names the file and both figures.
    """
    from abm.arena import map_parts
    from abm.memory import ENV

    folder = tmp_path_factory.mktemp("map")
    if suffix == ".png":
        path = _write(folder, huge_png(cols, rows), suffix)
    else:  # one free pixel; the rest of the (sparse) file is read only if the map fits
        path = folder / "fuzzed.npy"
        np.lib.format.open_memmap(path, mode="w+", dtype=bool, shape=(rows, cols))[0, 0] = True
    need = sum(map_parts((rows, cols)).values())
    with pytest.MonkeyPatch.context() as patch, case("map-file:memory budget", [str(path)]):
        patch.setenv(ENV, str(budget))
        try:
            Arena.from_bitmap(path)
        except MapError as exc:
            if rows * cols <= MAX_MAP_PIXELS and need > budget:
                assert "would need ~" in str(exc) and "this machine allows" in str(exc)
            raise
        assert need <= budget


@pytest.mark.parametrize("model", sorted(MAP_PARAMS))
def test_fuzzed_map_files_run_every_model_or_raise_naming_the_input(model, tmp_path_factory):
    key = MAP_PARAMS[model]

    @examples(40)
    @given(file=MODEL_FILES, seed=st.integers(0, 2**32 - 1))
    def one(file, seed):
        path = _write(tmp_path_factory.mktemp("map"), *file)
        with case(f"map-file:{model}", [str(path), f"'{path.stem}'"]):
            instance = model_class(model)(seed=seed, **{key: str(path)})
            instance.run(until=min(SHORT, instance.params.time_limit))

    one()


# Regression tests: one per defect the fuzzing found.
def test_a_header_claiming_a_huge_image_is_refused_before_decoding(tmp_path):
    for width, height in [(100_000, 100_000), (10_000, 9_000)]:  # Pillow's limit, then ours
        path = _write(tmp_path, huge_png(width, height), ".png")
        with pytest.raises(MapError, match=f"{path}.* more than 5e\\+07"):
            Arena.from_bitmap(path)


def test_a_map_without_free_pixels_names_the_file(tmp_path):
    path = _write(tmp_path, png_bytes(np.zeros((5, 5), bool), "L", "PNG"), ".png")
    with pytest.raises(MapError, match=f"{path}.*no free cell"):
        Arena.from_bitmap(path)


@pytest.mark.parametrize(
    ("model", "match"),
    [("hierarchy", "the world '{}' is"), ("sugarmap", "n_explorers=4 in arena '{}'")],
)
def test_a_swarm_that_does_not_fit_a_one_pixel_map_names_the_file(tmp_path, model, match):
    path = _write(tmp_path, png_bytes(np.ones((1, 1), bool), "L", "PNG"), ".png")
    with pytest.raises(ConfigError, match=match.format(path)):
        model_class(model)(seed=1, **{MAP_PARAMS[model]: str(path)})
