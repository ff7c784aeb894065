"""The code in docs/physics.md runs, and the figures it shows exist."""

from pathlib import Path

import pytest

pytest.importorskip("mujoco", reason="needs the physics extra: pip install mujoco")

from docs_helpers import DOCS, run_python_blocks


def test_physics_guide_code_runs():
    namespace = run_python_blocks("physics.md", min_blocks=1)
    assert namespace["g"].complete and len(namespace["gs"]) == 2


def test_physics_guide_images_exist():
    text = (DOCS / "physics.md").read_text()
    for name in ("images/physics_square.gif", "images/physics_grasps.png"):
        assert name in text and Path(DOCS / name).stat().st_size > 0
