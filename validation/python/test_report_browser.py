"""`glassscan report` pages opened in a real browser: Debian's Chromium (/usr/bin/chromium, or the
path in $CHROMIUM; `.ci/run` installs the distribution's package when it is absent), driven
headless by Playwright.

Runs the release binary (or the path in $GLASSSCAN) to make a small scan-angle study and a
small locate run (one or three poses, few photons), writes each one's report, and opens it:
the page must load with no console error, no page error and no request beyond its own file,
every figure (each <svg>) must render with a non-zero size and drawn content, and a full-page
screenshot (written to pytest's temporary directory, never into the repository) must be an
image with something on it.
"""

import os
import subprocess
from pathlib import Path

import pytest
from PIL import Image
from playwright.sync_api import sync_playwright

REPO = Path(__file__).resolve().parents[2]
BINARY = Path(os.environ.get("GLASSSCAN", REPO / "target" / "release" / "glassscan"))
CHROMIUM = Path(os.environ.get("CHROMIUM", "/usr/bin/chromium"))


def run(*args):
    subprocess.run([str(BINARY), *args], cwd=REPO, check=True, capture_output=True)


@pytest.fixture(scope="module")
def reports(tmp_path_factory):
    """The report.html of a small study and of a small locate run."""
    study = tmp_path_factory.mktemp("study") / "run"
    run("study", "scan-angle", "scenes/edge_study.toml", "--positions", "1",
        "--sweep-deg", "10:40:30", "--exposures-ms", "0.5", "--no-map",
        "--photons", "16384", "--out", str(study))
    locate = tmp_path_factory.mktemp("locate") / "run"
    run("locate", "scenes/edge_study_bare.toml", "--poses", "3", "--photons", "16384",
        "--out", str(locate))
    for d in (study, locate):
        run("report", str(d))
    return {"study": study / "report.html", "locate": locate / "report.html"}


@pytest.fixture(scope="module")
def browser():
    if not CHROMIUM.is_file():
        pytest.fail(f"{CHROMIUM} is missing: install Debian's chromium package "
                    "(apt-get install -y chromium), as .ci/run does")
    with sync_playwright() as p:
        # Root (as CI runs) cannot use Chromium's sandbox.
        b = p.chromium.launch(executable_path=str(CHROMIUM), headless=True,
                              args=["--no-sandbox"])
        yield b
        b.close()


@pytest.mark.parametrize("kind", ["study", "locate"])
def test_report_loads_and_every_figure_renders(reports, browser, kind, tmp_path):
    path = reports[kind]
    html = path.read_text(encoding="utf-8")
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    problems = []
    page.on("console", lambda m: problems.append(f"console {m.type}: {m.text}")
            if m.type in ("error", "warning") else None)
    page.on("pageerror", lambda e: problems.append(f"page error: {e}"))
    page.on("requestfailed", lambda r: problems.append(f"request failed: {r.url}"))
    requests = []
    page.on("request", lambda r: requests.append(r.url))
    page.goto(path.as_uri(), wait_until="load")

    assert problems == []
    # Self-contained: the page's own file is the only thing loaded.
    assert [u for u in requests if u != path.as_uri()] == []
    assert page.title().startswith({"study": "Scan-angle study", "locate": "Locate run"}[kind])

    figures = page.eval_on_selector_all(
        "svg",
        """els => els.map(e => {
            const r = e.getBoundingClientRect();
            const b = e.getBBox();
            return {w: r.width, h: r.height, bw: b.width, bh: b.height,
                    shapes: e.querySelectorAll('rect,line,polyline,circle,path,text').length};
        })""",
    )
    assert len(figures) == html.count("<svg") and len(figures) >= 2, figures
    for f in figures:
        assert f["w"] > 100 and f["h"] > 100, f
        assert f["bw"] > 0 and f["bh"] > 0 and f["shapes"] > 10, f

    shot = tmp_path / f"{kind}.png"
    page.screenshot(path=str(shot), full_page=True)
    page.close()
    image = Image.open(shot).convert("L")
    assert image.width >= 1280 and image.height > 900
    lo, hi = image.getextrema()
    assert hi - lo > 100, "the screenshot is blank"
    # Ink on a substantial share of the page: text, tables and figures, not a white sheet.
    dark = sum(image.histogram()[:160])
    assert dark > 0.002 * image.width * image.height
