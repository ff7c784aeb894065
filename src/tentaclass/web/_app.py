"""The FastAPI application behind ``tentaclass serve``: one page and a JSON API."""

from __future__ import annotations

import io
import logging
import re
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Literal

import numpy as np
from fastapi import FastAPI, File, Request, UploadFile
from fastapi.exceptions import RequestValidationError
from fastapi.responses import FileResponse, JSONResponse
from fastapi.staticfiles import StaticFiles
from pydantic import BaseModel, Field, model_validator

from .. import __version__, angles_to_points, grasp_state, resample_closed, wrap
from ..cli.options import parse_angle_list
from ..errors import InputError
from ..shapes import as_outline, from_mask, from_stroke
from ..wrapping import link_length_for_laps
from ._recognizer import (
    MIN_EXAMPLES,
    OUTLINE_POINTS,
    NameTakenError,
    Recognizer,
    UnknownShapeError,
)

if TYPE_CHECKING:  # FastAPI's ASGI types, from the framework it is built on
    from starlette.types import ASGIApp, Message, Receive, Scope, Send

__all__ = ["MAX_POINTS", "MAX_UPLOAD_BYTES", "create_app"]

log = logging.getLogger(__name__)

#: Largest upload (PNG image or CSV) the server reads, in bytes.
MAX_UPLOAD_BYTES = 2 * 2**20
#: Largest request body of any kind, in bytes.
MAX_BODY_BYTES = 8 * 2**20
#: Most points in one stroke or outline.
MAX_POINTS = 20_000
#: Most joint angles in one chain, and most chains in one CSV.
MAX_JOINTS = 5_000
MAX_ROWS = 100
#: Most pixels in an uploaded image.
MAX_PIXELS = 4_000_000

_NON_FINITE = re.compile(r"\b(?:nan|inf|infinity)\b", re.IGNORECASE)

Points = list[Annotated[list[float], Field(min_length=2, max_length=2)]]


class ShapeIn(BaseModel):
    """An object as a raw drawn stroke or a clean closed outline: give one of the two."""

    stroke: Points | None = Field(
        None, max_length=MAX_POINTS, description="Pointer trace as drawn, [[x, y], ...]."
    )
    outline: Points | None = Field(
        None, max_length=MAX_POINTS, description="Closed outline, [[x, y], ...]."
    )

    @model_validator(mode="after")
    def _one_of(self):
        if (self.stroke is None) == (self.outline is None):
            raise ValueError("give either 'stroke' or 'outline'")
        return self

    def to_outline(self) -> np.ndarray:
        if self.stroke is not None:
            return from_stroke(self.stroke, OUTLINE_POINTS)
        if self.outline is None:  # not reached: the model's validator asks for one of the two
            raise InputError("give either 'stroke' or 'outline'")
        return as_outline(self.outline, "outline")


class WrapIn(ShapeIn):
    """A shape and the chain to wrap around it."""

    links: int = Field(64, ge=2, le=1000, description="Links of the chain.")
    link_length: float | None = Field(
        None, gt=0, le=10, description="Link length as a fraction of the outline's perimeter."
    )
    laps: float | None = Field(
        None, gt=0, le=20, description="Choose the link length so the chain wraps this many laps."
    )
    mode: Literal["taut", "hug"] = "hug"
    direction: Literal["ccw", "cw"] = "ccw"
    start: float = Field(0.0, ge=0, lt=1, description="Start point, fraction of the perimeter.")
    offset: float = Field(
        0.0, ge=0, le=5, description="Stand-off of the base, as a fraction of the perimeter."
    )
    noise: float = Field(0.0, ge=0, le=1, description="Joint noise sigma (radians).")
    seed: int | None = Field(None, ge=0, description="Seed of the noise.")


class TeachIn(BaseModel):
    """A new shape's name and a few drawn examples of it."""

    name: str = Field(..., description="Name of the new shape.")
    strokes: list[Points] = Field(..., max_length=50, description="Drawn examples.")


class AnglesIn(BaseModel):
    """Joint angles measured on a chain: CSV text or a list of numbers."""

    csv: str | None = Field(
        None,
        max_length=MAX_UPLOAD_BYTES,
        description="Radians; one chain per line (or one angle per line for a single chain).",
    )
    angles: list[float] | None = Field(None, max_length=MAX_JOINTS)
    link_length: float = Field(1.0, gt=0, description="Link length of the chain.")

    @model_validator(mode="after")
    def _one_of(self):
        if (self.csv is None) == (self.angles is None):
            raise ValueError("give either 'csv' or 'angles'")
        return self


def _error(status: int, message: str) -> JSONResponse:
    return JSONResponse({"detail": message}, status_code=status)


def parse_angles_csv(text: str) -> list[np.ndarray]:
    """Chains of joint angles from CSV text: one per line, or one column for a single chain.

    Values are separated by commas, semicolons or white space and may be
    expressions of pi (``pi/2``), as ``tentaclass classify`` reads them; ``#``
    starts a comment. Raises :class:`~tentaclass.errors.InputError` naming the
    line of anything that is not a finite number.
    """
    rows = []
    for k, line in enumerate(text.splitlines(), start=1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        if _NON_FINITE.search(line):
            raise InputError(f"CSV line {k} contains NaN or infinite values")
        try:
            row = parse_angle_list(line)
        except ValueError as exc:
            raise InputError(f"CSV line {k}: {exc}") from None
        if not np.all(np.isfinite(row)):
            raise InputError(f"CSV line {k} contains NaN or infinite values")
        rows.append(row)
    if not rows:
        raise InputError("the CSV holds no joint angles")
    if all(len(r) == 1 for r in rows):
        rows = [np.concatenate(rows)]
    if len(rows) > MAX_ROWS:
        raise InputError(f"the CSV holds {len(rows)} chains; at most {MAX_ROWS} at once")
    for k, r in enumerate(rows, start=1):
        if not 3 <= len(r) <= MAX_JOINTS:
            raise InputError(f"chain {k} has {len(r)} joint angles; 3 to {MAX_JOINTS} are needed")
    return rows


def _perimeter(outline: np.ndarray) -> float:
    return float(np.sum(np.hypot(*(np.roll(outline, -1, axis=0) - outline).T)))


def _grasp(q: np.ndarray) -> dict:
    if len(q) == 0:
        return {"state": "partial", "laps": 0.0, "offset_links": 0}
    g = grasp_state(q)
    return {
        "state": str(g.state),
        "laps": float(g.laps),
        "offset_links": int(g.offset_links),
    }


def _chain_result(recognizer: Recognizer, q: np.ndarray, link_length: float) -> dict:
    answer, closed = recognizer.classify_chain(q, link_length)
    joints = angles_to_points(q, link_length)
    return {
        "angles": q.tolist(),
        "joints": joints.tolist(),
        "grasp": _grasp(q),
        "full_lap": closed,
        **answer.to_dict(),
    }


def _read_limited(upload: UploadFile) -> bytes:
    data = upload.file.read(MAX_UPLOAD_BYTES + 1)
    if len(data) > MAX_UPLOAD_BYTES:
        raise _TooLarge(f"the file is larger than {MAX_UPLOAD_BYTES // 2**20} MB")
    return data


class _TooLarge(InputError):
    pass


class _BodyLimit:
    """Refuse request bodies over ``limit`` bytes, by Content-Length or as they stream in.

    The body is read here (at most ``limit`` bytes are held) and handed on in one piece.
    """

    def __init__(self, app: ASGIApp, limit: int) -> None:
        self.app = app
        self.limit = limit

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        too_large = _error(413, f"request body larger than {self.limit // 2**20} MB")
        size = dict(scope.get("headers", ())).get(b"content-length", b"")
        if size.isdigit() and int(size) > self.limit:
            return await too_large(scope, receive, send)
        chunks: list[bytes] = []
        seen = 0
        while True:
            msg = await receive()
            if msg["type"] != "http.request":  # the client went away
                return None
            chunks.append(msg.get("body", b""))
            seen += len(chunks[-1])
            if seen > self.limit:
                return await too_large(scope, receive, send)
            if not msg.get("more_body", False):
                break
        body = b"".join(chunks)
        sent = False

        async def replay() -> Message:
            nonlocal sent
            if not sent:
                sent = True
                return {"type": "http.request", "body": body, "more_body": False}
            return await receive()

        return await self.app(scope, replay, send)


def _image_mask(data: bytes) -> np.ndarray:
    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(io.BytesIO(data)) as im:
            if im.format != "PNG":
                raise InputError(f"the file is a {im.format} image; upload a PNG")
            if im.width * im.height > MAX_PIXELS:
                raise _TooLarge(
                    f"the image has {im.width} x {im.height} pixels; at most "
                    f"{MAX_PIXELS // 10**6} million"
                )
            im.load()
            rgba = im.convert("RGBA")
    except (UnidentifiedImageError, OSError, Image.DecompressionBombError) as exc:
        raise InputError(f"the file is not a PNG image ({type(exc).__name__})") from None
    arr = np.asarray(rgba, dtype=float)
    gray = arr[..., :3].mean(axis=-1)
    alpha = arr[..., 3]
    if np.ptp(alpha) > 0:  # transparent background: the object is what is opaque
        return alpha > 127
    # dark object on light background, or light on dark: the object does not cover the border
    mask = gray < (gray.min() + gray.max()) / 2
    border = np.concatenate([mask[0], mask[-1], mask[1:-1, 0], mask[1:-1, -1]])
    return ~mask if border.mean() > 0.5 else mask


def create_app(data_dir: str | Path | None = None, recognizer: Recognizer | None = None) -> FastAPI:
    """The web application: the drawing page at ``/`` and the JSON API under ``/api``.

    Parameters
    ----------
    data_dir : path, optional
        Where taught shapes and the model file are kept (None: in memory only).
    recognizer : Recognizer, optional
        Use this recogniser instead of building one (tests share one).

    Returns
    -------
    fastapi.FastAPI
        Serve it with any ASGI server, e.g. ``uvicorn.run(create_app())``.
        The OpenAPI page is at ``/docs``.
    """
    rec = recognizer if recognizer is not None else Recognizer(data_dir)
    app = FastAPI(
        title="tentaclass",
        version=__version__,
        description=(
            "Draw an object, wrap a simulated tentacle around it and recognise it; "
            "recognise chains from measured joint angles; teach new shapes. "
            "Errors are JSON objects with a 'detail' message."
        ),
    )
    app.state.recognizer = rec
    static = resources.files("tentaclass.web") / "static"

    app.add_middleware(_BodyLimit, limit=MAX_BODY_BYTES)

    @app.exception_handler(RequestValidationError)
    async def _invalid(request: Request, exc: RequestValidationError) -> JSONResponse:
        parts = []
        for e in exc.errors()[:3]:
            loc = tuple(e.get("loc", ()))
            if e.get("type") == "json_invalid":  # loc is ("body", character)
                why = (e.get("ctx") or {}).get("error", "")
                at = f" at character {loc[1]}" if len(loc) > 1 else ""
                parts.append(f"the request body is not valid JSON{at}: {why}".rstrip(": "))
                continue
            if e.get("type") == "missing" and loc == ("body",):
                parts.append("the request body is empty: send a JSON object")
                continue
            where = ".".join(str(x) for x in loc if x not in ("body",))
            msg = str(e.get("msg", "invalid")).removeprefix("Value error, ")
            parts.append(f"{where}: {msg}" if where else msg)
        errors = [
            {"loc": [str(x) for x in e.get("loc", ())], "msg": str(e.get("msg")),
             "type": str(e.get("type"))}
            for e in exc.errors()[:10]
        ]  # fmt: skip
        return JSONResponse(
            {"detail": "; ".join(parts) or "invalid request", "errors": errors}, status_code=422
        )

    @app.exception_handler(InputError)
    async def _bad_input(request: Request, exc: InputError) -> JSONResponse:
        status = 400
        if isinstance(exc, NameTakenError):
            status = 409
        elif isinstance(exc, UnknownShapeError):
            status = 404
        elif isinstance(exc, _TooLarge):
            status = 413
        return _error(status, str(exc).splitlines()[0] if str(exc) else "bad input")

    @app.exception_handler(ValueError)
    async def _bad_value(request: Request, exc: ValueError) -> JSONResponse:
        return _error(400, str(exc).splitlines()[0] if str(exc) else "bad input")

    @app.exception_handler(Exception)
    async def _unexpected(request: Request, exc: Exception) -> JSONResponse:
        log.exception("unexpected error on %s", request.url.path)
        return _error(500, f"internal error ({type(exc).__name__}); the server keeps running")

    @app.get("/", include_in_schema=False)
    def page() -> FileResponse:
        return FileResponse(str(static / "index.html"))

    app.mount("/static", StaticFiles(directory=str(static)), name="static")

    @app.post("/api/outline", summary="Clean a drawn stroke into a closed outline")
    def api_outline(shape: ShapeIn) -> dict:
        """The cleaned outline of a stroke (see `tentaclass.shapes.from_stroke`)."""
        return {"outline": shape.to_outline().tolist()}

    @app.post("/api/outline/image", summary="Outline of the largest object in a PNG")
    def api_outline_image(file: Annotated[UploadFile, File(description="PNG silhouette")]) -> dict:
        """Outline of the largest object in a PNG silhouette, at most 2 MB."""
        mask = _image_mask(_read_limited(file))
        outline = resample_closed(from_mask(mask), OUTLINE_POINTS)
        return {"outline": outline.tolist(), "size": list(mask.shape[::-1])}

    @app.post("/api/classify", summary="Recognise a drawn stroke or an outline")
    def api_classify(shape: ShapeIn) -> dict:
        """Class probabilities of the shape; `label` is "unknown" when nothing fits."""
        outline = shape.to_outline()
        return {"outline": outline.tolist(), **rec.classify_outline(outline).to_dict()}

    @app.post("/api/wrap", summary="Wrap a simulated chain around a shape")
    def api_wrap(req: WrapIn) -> dict:
        """Joint angles and joint positions of the chain, its grasp state and its answer."""
        outline = req.to_outline()
        per = _perimeter(outline)
        offset = req.offset * per
        if req.link_length is not None and req.laps is not None:
            raise InputError("give either link_length or laps, not both")
        if req.laps is not None:
            ln = link_length_for_laps(
                outline, req.links, req.laps, start=req.start, direction=req.direction,
                mode=req.mode, offset=offset,
            )  # fmt: skip
        else:
            ln = (req.link_length if req.link_length is not None else 1.0 / req.links) * per
        w = wrap(
            outline, req.links, ln, start=req.start, direction=req.direction, mode=req.mode,
            offset=offset, noise=req.noise, random_state=req.seed,
        )  # fmt: skip
        q = np.asarray(w.angles)
        out = {
            "outline": outline.tolist(),
            "link_length": ln,
            "perimeter": per,
            "angles": q.tolist(),
            "joints": np.asarray(w.joints).tolist(),
            "contact": np.asarray(w.contact).tolist(),
            "complete": bool(w.complete),
            "laps": float(w.laps),
            "grasp": _grasp(q),
            "label": None,
            "probabilities": {},
            "full_lap": False,
        }
        if len(q) >= 3:
            answer, closed = rec.classify_chain(q, ln)
            out.update(answer.to_dict(), full_lap=closed)
        return out

    @app.post("/api/angles", summary="Recognise chains from measured joint angles")
    def api_angles(req: AnglesIn) -> dict:
        """Per chain: the reconstructed joints, the grasp state and the answer."""
        if req.csv is not None:
            rows = parse_angles_csv(req.csv)
        else:
            rows = [np.asarray(req.angles, dtype=float)]
            if not np.all(np.isfinite(rows[0])) or len(rows[0]) < 3:
                raise InputError("angles must be at least 3 finite numbers")
        return {"chains": [_chain_result(rec, q, req.link_length) for q in rows]}

    @app.post("/api/angles/file", summary="Recognise chains from a CSV file of joint angles")
    def api_angles_file(
        file: Annotated[UploadFile, File(description="CSV of joint angles")],
        link_length: float = 1.0,
    ) -> dict:
        """As `/api/angles`, from an uploaded CSV file of at most 2 MB."""
        data = _read_limited(file)
        try:
            text = data.decode("utf-8-sig")
        except UnicodeDecodeError:
            raise InputError("the file is not UTF-8 text: upload a CSV") from None
        if not link_length > 0 or not np.isfinite(link_length):
            raise InputError("link_length must be a finite number > 0")
        rows = parse_angles_csv(text)
        return {"chains": [_chain_result(rec, q, link_length) for q in rows]}

    @app.get("/api/classes", summary="Shapes the recogniser knows")
    def api_classes() -> dict:
        """Built-in and taught shapes."""
        return {"classes": rec.classes(), "min_examples": MIN_EXAMPLES}

    @app.post("/api/teach", summary="Teach a new shape from a few drawings", status_code=201)
    def api_teach(req: TeachIn) -> dict:
        """Learn a new shape; it is recognised from then on and kept in the data directory."""
        rec.teach(req.name, req.strokes)
        saved = rec.model_file is not None
        return {"classes": rec.classes(), "saved": saved}

    @app.delete("/api/classes/{name}", summary="Remove a taught shape")
    def api_forget(name: str) -> dict:
        """Forget a taught shape (built-in shapes stay)."""
        rec.forget(name)
        return {"classes": rec.classes()}

    return app
