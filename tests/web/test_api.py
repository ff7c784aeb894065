import io

import numpy as np
import pytest

pytest.importorskip("fastapi")
pytest.importorskip("httpx")

from _web_helpers import CROSS, figure_eight, hand_drawn
from fastapi.testclient import TestClient
from PIL import Image, ImageDraw

from tentaclass import (
    FourierClassifier,
    angles_to_points,
    grasp_state,
    load_model,
    points_to_angles,
    resample_closed,
)
from tentaclass.datasets import DRAWN_CLASSES, drawn_shapes
from tentaclass.shapes import from_stroke, square
from tentaclass.web import N_LINKS, Recognizer, create_app


@pytest.fixture(scope="module")
def client(recognizer, tmp_path_factory):
    app = create_app(recognizer=recognizer)
    return TestClient(app, raise_server_exceptions=False)


@pytest.fixture
def fresh(tmp_path):
    """A client whose recogniser keeps taught shapes in its own folder."""
    rec = Recognizer(tmp_path, n_per_class=15)
    return TestClient(create_app(recognizer=rec), raise_server_exceptions=False), rec, tmp_path


def _world(stroke):
    """Screen strokes (y down) as the page sends them (y up)."""
    return (np.asarray(stroke) * [1, -1]).tolist()


def test_classify_each_drawn_class(client):
    d = drawn_shapes(2, random_state=11)
    for stroke, cls in zip(d.strokes, d.target, strict=True):
        r = client.post("/api/classify", json={"stroke": _world(stroke)})
        assert r.status_code == 200, r.text
        body = r.json()
        assert body["label"] == cls
        assert set(body["probabilities"]) == set(DRAWN_CLASSES)
        assert sum(body["probabilities"].values()) == pytest.approx(1.0)
        assert len(body["outline"]) == 256


def test_default_model_recognises_drawn_shapes(recognizer):
    """>= 98 % of unseen drawn strokes, every class, rejections counted as errors."""
    d = drawn_shapes(30, random_state=2024)
    predicted = np.array([recognizer.classify_stroke(s).label for s in d.strokes])
    assert np.mean(predicted == d.target) >= 0.98
    for cls in DRAWN_CLASSES:
        assert np.mean(predicted[d.target == cls] == cls) >= 0.9, cls


def test_page_recogniser_agrees_with_the_library(client):
    """The API's answer equals the library pipeline built by hand from public functions."""
    train = drawn_shapes(40, random_state=0)
    X = np.array(
        [points_to_angles(resample_closed(from_stroke(s, 256), N_LINKS)) for s in train.strokes]
    )
    lib = FourierClassifier(spread="auto", reject_below=1e-50).fit(X, train.target)
    test = drawn_shapes(3, random_state=99)
    for stroke in test.strokes:
        world = np.asarray(_world(stroke))
        q = points_to_angles(resample_closed(from_stroke(world, 256), N_LINKS))
        body = client.post("/api/classify", json={"stroke": world.tolist()}).json()
        assert body["label"] == lib.predict(q[None])[0]
        assert list(body["probabilities"].values()) == pytest.approx(
            lib.predict_proba(q[None])[0].tolist(), abs=1e-9
        )


def test_unknown_when_nothing_fits(client):
    r = client.post("/api/classify", json={"outline": (CROSS * 100).tolist()})
    assert r.status_code == 200
    assert r.json()["label"] == "unknown"


def test_wrap_square_one_lap(client):
    outline = square(200.0) + 300
    r = client.post(
        "/api/wrap", json={"outline": outline.tolist(), "links": 32, "link_length": 1 / 32}
    )
    assert r.status_code == 200, r.text
    body = r.json()
    q = np.array(body["angles"])
    assert q.shape == (32,)
    assert body["link_length"] == pytest.approx(800 / 32)
    assert body["grasp"]["state"] == grasp_state(q).state.item() == "once"
    joints = np.array(body["joints"])
    assert joints.shape == (33, 2)
    assert np.allclose(np.hypot(*np.diff(joints, axis=0).T), 25.0)
    assert body["label"] == "square"
    assert body["complete"] and body["full_lap"]


@pytest.mark.parametrize("mode", ["taut", "hug"])
def test_wrap_with_laps_and_offset(client, mode):
    outline = hand_drawn(square(1.0), seed=3)
    body = {"stroke": outline.tolist(), "links": 40, "laps": 1.5, "mode": mode, "offset": 0.05}
    r = client.post("/api/wrap", json=body)
    assert r.status_code == 200, r.text
    got = r.json()
    assert got["grasp"]["offset_links"] >= 1
    assert got["grasp"]["state"] == "multiple"
    assert 1.2 < got["grasp"]["laps"] < 1.8


@pytest.mark.parametrize(
    ("body", "status", "text"),
    [
        ({"stroke": []}, 400, "empty"),
        ({"stroke": [[1.0, 2.0]]}, 400, "1 distinct point"),
        ({"stroke": [[1.0, 2.0]] * 5}, 400, "1 distinct point"),
        ({"stroke": [[0, 0], [1, 1], [2, 2], [3, 3]]}, 400, "no area"),
        ({"stroke": figure_eight().tolist()}, 400, "crosses itself"),
        ({"stroke": [[0, 0, 1]]}, 422, "stroke"),
        ({}, 422, "either 'stroke' or 'outline'"),
        ({"stroke": [[0, 0]] * 20_001}, 422, "stroke"),
    ],
)
def test_bad_strokes(client, body, status, text):
    for path in ("/api/classify", "/api/wrap"):
        r = client.post(path, json=body)
        assert r.status_code == status, r.text
        assert text in r.json()["detail"]


def test_wrap_bad_chain(client):
    outline = (square(100.0)).tolist()
    r = client.post("/api/wrap", json={"outline": outline, "links": 1})
    assert r.status_code == 422 and "links" in r.json()["detail"]
    r = client.post("/api/wrap", json={"outline": outline, "laps": 1, "link_length": 0.1})
    assert r.status_code == 400 and "either link_length or laps" in r.json()["detail"]
    r = client.post("/api/wrap", json={"outline": outline, "links": 4, "laps": 3})
    assert r.status_code == 400 and "cannot close" in r.json()["detail"]


def _png(draw_star=True, size=(200, 200)):
    im = Image.new("L", size, 255)
    if draw_star:
        t = np.pi / 2 + np.arange(10) * np.pi / 5
        r = np.where(np.arange(10) % 2 == 0, 80, 35)
        ImageDraw.Draw(im).polygon(
            list(zip(100 + r * np.cos(t), 100 - r * np.sin(t), strict=True)), fill=0
        )
    buf = io.BytesIO()
    im.save(buf, format="PNG")
    return buf.getvalue()


def test_png_upload(client):
    r = client.post("/api/outline/image", files={"file": ("star.png", _png(), "image/png")})
    assert r.status_code == 200, r.text
    outline = r.json()["outline"]
    assert client.post("/api/classify", json={"outline": outline}).json()["label"] == "star"


def test_bad_uploads(client):
    files = {"file": ("a.png", b"not an image at all", "image/png")}
    r = client.post("/api/outline/image", files=files)
    assert r.status_code == 400 and "not a PNG" in r.json()["detail"]
    buf = io.BytesIO()
    Image.new("L", (20, 20)).save(buf, format="JPEG")
    r = client.post("/api/outline/image", files={"file": ("a.jpg", buf.getvalue(), "image/jpeg")})
    assert r.status_code == 400 and "JPEG" in r.json()["detail"]
    r = client.post("/api/outline/image", files={"file": ("e.png", _png(False), "image/png")})
    assert r.status_code == 400 and "no foreground" in r.json()["detail"]
    big = b"\x89PNG" + bytes(3 * 2**20)
    r = client.post("/api/outline/image", files={"file": ("big.png", big, "image/png")})
    assert r.status_code == 413 and "larger than 2 MB" in r.json()["detail"]
    huge = bytes(9 * 2**20)
    r = client.post("/api/classify", content=huge, headers={"content-type": "application/json"})
    assert r.status_code == 413


def test_angles_csv_round_trip(client):
    stroke = hand_drawn(square(1.0), seed=5)
    w = client.post("/api/wrap", json={"stroke": stroke.tolist(), "links": 48,
                                       "link_length": 1 / 40}).json()  # fmt: skip
    text = "\n".join(f"{a:.17g}" for a in w["angles"])  # one angle per line: one chain
    r = client.post("/api/angles", json={"csv": text, "link_length": w["link_length"]})
    assert r.status_code == 200, r.text
    (chain,) = r.json()["chains"]
    assert chain["label"] == w["label"] == "square"
    assert chain["grasp"] == w["grasp"]
    rebuilt = angles_to_points(w["angles"], w["link_length"])
    assert np.allclose(chain["joints"], rebuilt)
    # the chain's shape: the rebuilt joints are the wrap's joints, moved and turned
    j = np.array(w["joints"])
    assert np.allclose(np.hypot(*np.diff(rebuilt, axis=0).T), np.hypot(*np.diff(j, axis=0).T))
    # several chains, comma-separated, and the file upload
    two = "\n".join(", ".join(f"{a:.17g}" for a in w["angles"]) for _ in range(2))
    assert len(client.post("/api/angles", json={"csv": two}).json()["chains"]) == 2
    r = client.post("/api/angles/file", files={"file": ("q.csv", two.encode(), "text/csv")})
    assert r.status_code == 200 and len(r.json()["chains"]) == 2


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("0.1, 0.2, abc, 0.3", "'abc' is not a number"),
        ("0.1, nan, 0.2, 0.3", "NaN"),
        ("0.1\ninf\n0.2", "NaN or infinite"),
        ("", "no joint angles"),
        ("0.1, 0.2", "2 joint angles"),
    ],
)
def test_bad_csv(client, text, message):
    r = client.post("/api/angles", json={"csv": text})
    assert r.status_code == 400
    assert message in r.json()["detail"]


def test_bad_csv_file(client):
    r = client.post("/api/angles/file", files={"file": ("q.csv", b"\xff\xfe\x00bad", "text/csv")})
    assert r.status_code == 400 and "UTF-8" in r.json()["detail"]


def test_teach_recognise_save_remove(fresh):
    client, _, folder = fresh
    strokes = [hand_drawn(CROSS, seed=s).tolist() for s in range(3)]
    r = client.post("/api/teach", json={"name": "cross", "strokes": strokes[:1]})
    assert r.status_code == 400 and "at least 3" in r.json()["detail"]
    r = client.post("/api/teach", json={"name": "cross", "strokes": strokes})
    assert r.status_code == 201, r.text
    assert {"name": "cross", "builtin": False, "examples": 3} in r.json()["classes"]
    new = hand_drawn(CROSS, seed=42, size=150).tolist()
    assert client.post("/api/classify", json={"stroke": new}).json()["label"] == "cross"
    # built-in shapes are still recognised
    star = drawn_shapes(1, classes=("star",), random_state=8).strokes[0]
    assert client.post("/api/classify", json={"stroke": _world(star)}).json()["label"] == "star"
    # saved: the model file answers the same, and a new server knows the shape
    q = points_to_angles(resample_closed(from_stroke(new, 256), N_LINKS))
    assert load_model(folder / "model.tcm").predict(q[None])[0] == "cross"
    assert "cross" in [c["name"] for c in Recognizer(folder, n_per_class=15).classes()]
    # duplicate names, built-in or taught, in any case
    for name in ("cross", "Star"):
        r = client.post("/api/teach", json={"name": name, "strokes": strokes})
        assert r.status_code == 409 and "exists already" in r.json()["detail"]
    for name in ("", "a/b", "unknown"):
        assert client.post("/api/teach", json={"name": name, "strokes": strokes}).status_code == 400
    r = client.post("/api/teach", json={"name": "eight", "strokes": [figure_eight().tolist()] * 3})
    assert r.status_code == 400 and "crosses itself" in r.json()["detail"]
    # removal
    assert client.delete("/api/classes/star").status_code == 400
    assert client.delete("/api/classes/nothing").status_code == 404
    r = client.delete("/api/classes/cross")
    assert r.status_code == 200 and "cross" not in [c["name"] for c in r.json()["classes"]]
    assert client.post("/api/classify", json={"stroke": new}).json()["label"] != "cross"
    assert "cross" not in [c["name"] for c in Recognizer(folder, n_per_class=15).classes()]


def test_openapi_documents_the_api(client):
    spec = client.get("/openapi.json").json()
    for path in ("/api/wrap", "/api/classify", "/api/teach", "/api/angles", "/api/classes",
                 "/api/outline/image"):  # fmt: skip
        assert path in spec["paths"]
    assert client.get("/docs").status_code == 200


def test_page_and_modules_are_served(client):
    page = client.get("/")
    assert page.status_code == 200 and 'type="module"' in page.text
    for name in ("app.js", "api.js", "plot.js", "style.css"):
        r = client.get(f"/static/{name}")
        assert r.status_code == 200
        assert "http://" not in r.text and "https://" not in r.text  # no CDN: works offline


def test_bad_requests_do_not_disturb_other_users(fresh):
    """Many users at once, some sending garbage, one teaching: every good answer is right."""
    from concurrent.futures import ThreadPoolExecutor

    client, _, _ = fresh
    good = drawn_shapes(2, random_state=21)
    jobs = [("good", s, c) for s, c in zip(good.strokes, good.target, strict=True)]
    bad_bodies = [{"stroke": []}, {"stroke": figure_eight().tolist()}, {"outline": [[0, 0]] * 3}]
    jobs += [("bad", b, None) for b in bad_bodies * 4]
    jobs.append(("teach", [hand_drawn(CROSS, seed=s).tolist() for s in range(3)], "cross"))

    def run(job):
        kind, payload, cls = job
        if kind == "good":
            r = client.post("/api/classify", json={"stroke": _world(payload)})
            return r.status_code == 200 and r.json()["label"] == cls
        if kind == "bad":
            return 400 <= client.post("/api/classify", json=payload).status_code < 500
        return client.post("/api/teach", json={"name": cls, "strokes": payload}).status_code == 201

    order = np.random.default_rng(0).permutation(len(jobs))
    with ThreadPoolExecutor(6) as pool:
        results = list(pool.map(run, [jobs[i] for i in order]))
    assert all(results)


def test_streamed_body_over_the_limit_is_refused(client):
    def chunks():
        for _ in range(10):
            yield bytes(2**20)

    r = client.post("/api/classify", content=chunks(), headers={"content-type": "application/json"})
    assert r.status_code == 413 and "larger than 8 MB" in r.json()["detail"]
    assert client.get("/api/classes").status_code == 200


def test_csv_takes_expressions_of_pi_and_comments(client):
    text = "# a square, 16 links\n" + ", ".join(["0", "0", "0", "pi/2"] * 4)
    (chain,) = client.post("/api/angles", json={"csv": text}).json()["chains"]
    assert chain["angles"] == pytest.approx([0, 0, 0, np.pi / 2] * 4)
    assert chain["label"] == "square" and chain["grasp"]["state"] == "once"


@pytest.mark.parametrize(
    ("body", "message"),
    [
        (
            b"{not json",
            "the request body is not valid JSON at character 1: Expecting property name",
        ),
        (
            b'{"outline": [[0, 0], [1, 0],]}',
            "the request body is not valid JSON at character 28: Expecting value",
        ),
        (b"", "the request body is empty: send a JSON object"),
    ],
)
def test_malformed_json_is_named(client, body, message):
    r = client.post("/api/classify", content=body, headers={"content-type": "application/json"})
    assert r.status_code == 422 and r.json()["detail"].startswith(message), r.text


def test_link_length_beyond_float64_is_a_bad_request(client):
    # the joint positions of 1e308 links overflowed: a 400 naming 'points' and NaN
    r = client.post("/api/angles", json={"angles": [1.0, 1.0, 1.0], "link_length": 1e308})
    assert r.status_code == 400
    assert r.json()["detail"].startswith("link_lengths up to 1e+308 over 3 links")
    # a tiny length draws the same chain, scaled
    r = client.post("/api/angles", json={"angles": [1.0, 1.0, 1.0], "link_length": 1e-300})
    assert r.status_code == 200 and r.json()["chains"][0]["joints"][1][0] > 0


def test_concurrent_requests_all_answer(client):
    from concurrent.futures import ThreadPoolExecutor

    good = {"outline": square(100.0).tolist()}
    bad = {"outline": [[0, 0], [1, 1], [1, 0], [0, 1]]}
    with ThreadPoolExecutor(8) as pool:
        codes = list(pool.map(lambda b: client.post("/api/classify", json=b).status_code,
                              [good, bad] * 8))  # fmt: skip
    assert codes == [200, 400] * 8
