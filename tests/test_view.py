"""The interactive view: a self-contained HTML page holding the result's values, checked in a
real browser (headless Chromium) where one is installed."""

from __future__ import annotations

import json
import re
import shutil
import subprocess

import numpy as np
import pytest

from cloth.cli import main
from cloth.figures.view import FIELDS, grid_triangles, view_figure
from cloth.io import write_netcdf
from cloth.stages.results import aggregate
from tests.test_relax import solve, tube
from tests.test_results import relaxed_file

pytest.importorskip("plotly", reason="the view extra (plotly) is not installed")


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("view")
    state = tube({"cylinder": {"radius": 0.1, "bottom": 0.0, "top": 0.5}}, 0.2, n=32, m=6)
    ds = aggregate(relaxed_file(tmp, state, solve(state)))[0]
    result = write_netcdf(ds, tmp / "result.nc")
    assert main(["view", str(result), "-o", str(tmp / "garment.html")]) == 0
    return ds, tmp / "garment.html"


def test_the_page_carries_the_result_and_needs_no_network(page):
    ds, path = page
    text = path.read_text()
    assert not re.search(r"<script[^>]+src=[\"']?https?:", text)
    assert not re.search(r"<link[^>]+href=[\"']?https?:", text)
    assert '<meta name="cloth:nodes" content="192">' in text
    fields = json.loads(
        re.search(r'name="cloth:fields" content="([^"]+)"', text)[1].replace("&quot;", '"')
    )
    assert fields[:5] == list(FIELDS)[:5] and "indentation" not in fields  # a rigid body
    fig = view_figure(ds)
    garment = fig.data[-1]
    # the colours are the result's pressure at each node, the hover its row and column
    np.testing.assert_array_equal(garment.intensity, ds["pressure_mmHg"].values.ravel())
    custom = np.asarray(garment.customdata)
    assert custom[37, 0] == 37 // 32 and custom[37, 1] == 37 % 32
    np.testing.assert_allclose(custom[:, 3], ds["stress_weft"].values.ravel() / 1e3, rtol=1e-15)
    assert len(fig.layout.updatemenus[0].buttons) == len(fields)


def test_grid_triangles_cover_the_tube_once():
    tri = grid_triangles(4, 5, closed=True)
    assert tri.shape == (2 * 3 * 5, 3) and set(np.unique(tri)) == set(range(20))
    # every quad's two triangles together have area: no repeated corner
    assert all(len(set(t)) == 3 for t in tri.tolist())
    assert grid_triangles(4, 5, closed=False).shape == (2 * 3 * 4, 3)


def test_bad_result_gets_one_line(tmp_path, capsys):
    (tmp_path / "bad.nc").write_bytes(b"not netcdf")
    assert main(["view", str(tmp_path / "bad.nc"), "-o", str(tmp_path / "v.html")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "bad.nc" in err[0] and not (tmp_path / "v.html").exists()


CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
#: Records console errors and uncaught exceptions into the page (read back with --dump-dom).
RECORDER = """<script>
window.__errors = [];
const __error = console.error.bind(console);
console.error = (...a) => { window.__errors.push(a.map(String).join(" ")); __error(...a); };
window.addEventListener("error", e => window.__errors.push(String(e.message)));
window.addEventListener("load", () => setTimeout(() => {
  const pre = document.createElement("pre");
  pre.id = "recorded-errors";
  pre.textContent = JSON.stringify(window.__errors);
  document.body.appendChild(pre);
}, 2000));
</script>"""


def _chromium(*args, window: str = "1000,800"):
    flags = [
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--virtual-time-budget=15000",
        f"--window-size={window}",
    ]
    return subprocess.run([CHROMIUM, *flags, *args], capture_output=True, text=True, timeout=120)


@pytest.mark.browser
@pytest.mark.skipif(
    CHROMIUM is None,
    reason="no chromium (Debian package chromium; .ci/run installs it where apt is available)",
)
def test_a_real_browser_draws_the_garment_without_errors(page, tmp_path):
    import matplotlib.image

    _, path = page
    probe = tmp_path / "probe.html"
    probe.write_text(path.read_text().replace("<head>", "<head>" + RECORDER, 1))
    dom = _chromium("--dump-dom", probe.as_uri())
    recorded = re.search(r'<pre id="recorded-errors">(.*?)</pre>', dom.stdout, re.S)
    assert recorded, dom.stderr[-2000:]
    assert json.loads(recorded[1].replace("&quot;", '"')) == []
    assert "gl-canvas" in dom.stdout  # plotly drew the scene with WebGL
    shot = tmp_path / "shot.png"
    _chromium(f"--screenshot={shot}", path.as_uri())
    pixels = (matplotlib.image.imread(shot)[..., :3] * 255).round().astype(int)
    colours = np.unique(pixels.reshape(-1, 3), axis=0)
    assert len(colours) > 500, len(colours)  # a shaded surface, not a blank canvas
    # the garment, shaded colour, covers part of the scene (left of the colour bar); the body
    # and the background are grey
    scene = pixels[:, :800]
    chromatic = (scene.max(axis=2) - scene.min(axis=2)) > 40
    assert chromatic.mean() > 0.05, chromatic.mean()


@pytest.mark.browser
@pytest.mark.skipif(
    CHROMIUM is None,
    reason="no chromium (Debian package chromium; .ci/run installs it where apt is available)",
)
def test_the_first_camera_shows_a_whole_leg(tmp_path):
    """A stocking's garment.html at 1400 x 900: the garment (its shaded colours) spans most of
    the scene's height and touches neither its top nor its bottom (plotly's data aspect with
    its default camera cropped a leg at both ends)."""
    import matplotlib.image

    from tests.conftest import run_result

    case = {
        "material": "powernet",
        "body": {"leg": {"size": "M"}},
        "garment": {
            "bottom": 0.09,
            "top": 0.77,
            "reduction": 0.16,
            "grid": [12, 16],
            "edges": "sliding",
            "lengthwise_reduction": 0.15,
            "error_estimate": False,
        },
        "solver": {"method": "newton", "tolerance": 1.0e-8, "max_iterations": 150},
    }
    out = run_result(tmp_path / "leg", case)
    page = tmp_path / "garment.html"
    assert main(["view", str(out / "result.nc"), "-o", str(page)]) == 0
    shot = tmp_path / "shot.png"
    _chromium(f"--screenshot={shot}", page.as_uri(), window="1400,900")
    pixels = (matplotlib.image.imread(shot)[..., :3] * 255).round().astype(int)
    scene = pixels[100:, 200:1150]  # below the title and the menu, left of the colour bar
    chromatic = (scene.max(axis=2) - scene.min(axis=2)) > 40
    rows = np.flatnonzero(chromatic.any(axis=1))
    assert rows.size, "no garment drawn"
    height = scene.shape[0]
    assert rows[0] > 5 and rows[-1] < height - 5, (rows[0], rows[-1], height)
    assert (rows[-1] - rows[0]) / height > 0.5, (rows[0], rows[-1], height)
