"""The page in a real browser: Chromium (from the system) driven by Playwright.

One server (``tentaclass serve`` in a subprocess) and one browser serve all the
tests; each test opens a fresh page.
"""

import io
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from _web_helpers import CROSS, figure_eight, hand_drawn
from PIL import Image, ImageDraw

from tentaclass import angles_to_points
from tentaclass.datasets import DRAWN_CLASSES, drawn_shapes
from tentaclass.web import Recognizer

CHROMIUM = os.environ.get("TENTACLASS_CHROMIUM", "/usr/bin/chromium")
ARGS = [
    "--no-sandbox",
    "--headless",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
DOCS_IMAGES = Path(__file__).resolve().parents[2] / "docs" / "images"
TIMEOUT = 15_000  # ms


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    pytest.importorskip("fastapi")
    pytest.importorskip("uvicorn")
    data = tmp_path_factory.mktemp("serve-data")
    cmd = [sys.executable, "-m", "tentaclass", "serve", "--port", "0", "--data-dir", str(data)]
    log = data / "serve.log"
    with open(log, "w") as err:
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=err, text=True)
    try:
        line = proc.stdout.readline()
        match = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
        if not match:
            proc.kill()
            pytest.fail(f"tentaclass serve did not start: {line!r} {log.read_text()[-2000:]}")
        yield f"http://127.0.0.1:{match.group(1)}"
    finally:
        proc.terminate()
        proc.wait(timeout=30)
        proc.stdout.close()


@pytest.fixture(scope="module")
def browser():
    sync_api = pytest.importorskip("playwright.sync_api")
    if not (os.path.isfile(CHROMIUM) and os.access(CHROMIUM, os.X_OK)):
        pytest.skip(f"no Chromium at {CHROMIUM} (apt-get install chromium)")
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=ARGS, headless=True)
        yield b
        b.close()


@pytest.fixture
def page(browser, server):
    context = browser.new_context(viewport={"width": 1300, "height": 1000})
    pg = context.new_page()
    pg.set_default_timeout(TIMEOUT)
    pg.goto(server + "/")
    pg.wait_for_selector("#draw[data-ready='1']")
    pg.wait_for_selector("#classes li")
    yield pg
    context.close()


@pytest.fixture(scope="module")
def library():
    return Recognizer()


def _fit(stroke, lo=60.0, hi=540.0):
    """Screen points of a stroke scaled into the canvas (600 x 600)."""
    s = np.asarray(stroke, float)
    s = s - s.min(axis=0)
    s = s * ((hi - lo) / s.max()) + lo
    return s


def _act(page, action):
    """Run a user action and wait until the page has finished it (answer, chain, message)."""
    before = int(page.evaluate("() => Number(document.body.dataset.actions || 0)"))
    action()
    page.wait_for_function(
        f"() => Number(document.body.dataset.actions || 0) > {before} &&"
        " document.body.dataset.idle === '1'"
    )


def _draw(page, screen_points):
    """Draw a stroke with the mouse (pointerdown, moves, pointerup) and wait for the page."""
    box = page.locator("#draw").bounding_box()
    scale = box["width"] / 600.0
    xy = [(box["x"] + x * scale, box["y"] + y * scale) for x, y in screen_points]

    def draw():
        page.mouse.move(*xy[0])
        page.mouse.down()
        for x, y in xy[1:]:
            page.mouse.move(x, y)
        page.mouse.up()

    _act(page, draw)


def _label(page):
    return page.locator("#answer").get_attribute("data-label")


def _message(page):
    return page.locator("#message").inner_text() if page.locator("#message").is_visible() else ""


@pytest.mark.parametrize("cls", DRAWN_CLASSES)
def test_draw_each_shape(page, library, cls):
    """The answer shown is the class drawn, and the library's answer for the same points."""
    stroke = drawn_shapes(1, classes=(cls,), random_state=31).strokes[0]
    _draw(page, _fit(stroke))
    shown = _label(page)
    sent = np.array(page.evaluate("() => window.tentaclass.state.source.stroke"))
    assert len(sent) >= len(stroke)
    assert shown == library.classify_stroke(sent).label == cls
    bars = page.locator("#bars .bar")
    assert bars.count() == len(DRAWN_CLASSES)
    assert page.locator("#bars .bar.best").get_attribute("data-cls") == cls


def test_animation_end_state_and_chain_settings(page):
    star = drawn_shapes(1, classes=("star",), random_state=4).strokes[0]
    _draw(page, _fit(star))
    _label(page)
    canvas = page.locator("#draw")
    assert canvas.get_attribute("data-anim") == "done"
    assert canvas.get_attribute("data-links") == "64"
    wrap = page.evaluate("() => window.tentaclass.last.wrap")
    assert len(wrap["joints"]) == 65
    assert wrap["label"] == "star"  # the chain's own answer
    # the copyable text is the joint-angle array
    text = page.locator("#angles").input_value()
    assert np.allclose([float(t) for t in text.split(",")], wrap["angles"], atol=1e-6)
    assert page.locator("#grasp").get_attribute("data-state") == wrap["grasp"]["state"]
    # the picture in docs/web.md: TENTACLASS_DOCS_SCREENSHOT=1 pytest tests/web -k animation
    if os.environ.get("TENTACLASS_DOCS_SCREENSHOT"):
        DOCS_IMAGES.mkdir(exist_ok=True)
        page.screenshot(path=str(DOCS_IMAGES / "web-page.png"), full_page=True)
    # another chain: 20 links, taut, two laps, a stand-off
    page.fill("#links", "20")
    page.select_option("#mode", "taut")
    page.select_option("#sizeby", "laps")
    page.fill("#laps", "2")
    page.fill("#offset", "15")
    _act(page, lambda: page.click("#rewrap"))
    assert canvas.get_attribute("data-links") == "20"
    wrap = page.evaluate("() => window.tentaclass.last.wrap")
    assert len(wrap["joints"]) == 21
    assert wrap["grasp"]["state"] == "multiple"
    assert wrap["grasp"]["offset_links"] >= 1


def test_csv_round_trip(page):
    """Angles copied from a wrap, pasted as robot data: same chain, same answer."""
    square = drawn_shapes(1, classes=("square",), random_state=9).strokes[0]
    _draw(page, _fit(square))
    assert _label(page) == "square"
    wrap = page.evaluate("() => window.tentaclass.last.wrap")
    page.fill("#csv", page.locator("#angles").input_value())
    page.fill("#csvlink", repr(wrap["link_length"]))
    _act(page, lambda: page.click("#csvgo"))
    got = page.evaluate("() => window.tentaclass.last.angles.chains[0]")
    assert page.locator("#answer").get_attribute("data-label") == got["label"] == wrap["label"]
    assert np.allclose(got["angles"], wrap["angles"], atol=1e-6)  # six decimals in the text
    rebuilt = angles_to_points(got["angles"], wrap["link_length"])
    assert np.allclose(got["joints"], rebuilt)
    assert page.locator("#draw").get_attribute("data-links") == str(len(wrap["angles"]))


def _png(kind):
    buf = io.BytesIO()
    if kind == "text":
        return b"this is not a picture"
    im = Image.new("L", (240, 240), 255)
    ImageDraw.Draw(im).ellipse((20, 80, 220, 160), fill=0)
    im.save(buf, format="PNG")
    return buf.getvalue()


def test_bad_input_messages_and_png(page, tmp_path):
    _draw(page, [(300, 300), (300, 300)])  # a dot
    assert "distinct point" in _message(page)
    _draw(page, figure_eight() * [1, -1])
    assert "crosses itself" in _message(page)
    page.fill("#csv", "0.1, 0.2, oops")
    _act(page, lambda: page.click("#csvgo"))
    assert "'oops' is not a number" in _message(page)
    page.fill("#csv", "0.1, NaN, 0.3")
    _act(page, lambda: page.click("#csvgo"))
    assert "NaN" in _message(page)
    # a file that is not an image, then a real PNG (an ellipse)
    bad = tmp_path / "fake.png"
    bad.write_bytes(_png("text"))
    _act(page, lambda: page.set_input_files("#png", str(bad)))
    assert "not a PNG" in _message(page)
    good = tmp_path / "ellipse.png"
    good.write_bytes(_png("ellipse"))
    _act(page, lambda: page.set_input_files("#png", str(good)))
    assert _label(page) == "ellipse"
    assert _message(page) == ""
    assert page.locator("#draw").get_attribute("data-anim") == "done"
    # the server still answers after all that
    _draw(page, _fit(drawn_shapes(1, classes=("square",), random_state=2).strokes[0]))
    assert _label(page) == "square"


def _cross(seed, size=300.0):
    return _fit(hand_drawn(CROSS, seed=seed, size=size) * [1, -1])


def test_teach_a_new_shape(page):
    page.select_option("#speed", "0")
    _draw(page, _cross(0))
    page.click("#teachadd")
    page.fill("#teachname", "cross")
    _act(page, lambda: page.click("#teachgo"))
    assert "at least 3" in _message(page)  # one example is not enough
    for seed in (1, 2):
        _draw(page, _cross(seed))
        page.click("#teachadd")
    assert page.locator("#teachcount").inner_text() == "3 examples"
    page.fill("#teachname", "Star")
    _act(page, lambda: page.click("#teachgo"))
    assert "exists already" in _message(page)  # a built-in name
    page.fill("#teachname", "cross")
    _act(page, lambda: page.click("#teachgo"))
    assert page.locator("#classes li[data-cls='cross']").count() == 1
    assert page.locator("#teachcount").inner_text() == "0 examples"
    _draw(page, _cross(17, size=200))
    assert _label(page) == "cross"
    _act(page, lambda: page.click("#classes li[data-cls='cross'] button"))
    assert page.locator("#classes li[data-cls='cross']").count() == 0


def test_pen_and_touch_pointers(page):
    """Strokes from pen and touch pointers (synthetic pointer events) are drawn too."""
    circle = _fit(drawn_shapes(1, classes=("circle",), random_state=12).strokes[0])
    script = """([pts, kind]) => {
        const c = document.getElementById('draw');
        const r = c.getBoundingClientRect();
        const fire = (type, [x, y]) => c.dispatchEvent(new PointerEvent(type, {
            pointerId: 7, pointerType: kind, bubbles: true, isPrimary: true,
            clientX: r.left + x * r.width / 600, clientY: r.top + y * r.height / 600}));
        fire('pointerdown', pts[0]);
        pts.slice(1).forEach(p => fire('pointermove', p));
        fire('pointerup', pts[pts.length - 1]);
    }"""
    for kind in ("pen", "touch"):
        _act(page, lambda kind=kind: page.evaluate(script, [circle.tolist(), kind]))
        assert _label(page) == "circle"
