"""The linear object scanner on the thesis's grids and on a simulated belt.

Prints what :func:`tentaclass.scanner.inspect` says about the thesis's 5 x 5
test grids (its network called the square with a hole a "triangle"), streams
a simulated belt through a :class:`~tentaclass.scanner.LineScanner` one chunk
at a time, and draws two figures into the current directory:
``scanner_objects.png`` (objects with the expected outline and their defects)
and ``scanner_belt.png`` (the belt with boxes, labels and defect marks).

Run: ``python examples/scanner_demo.py``
"""

import matplotlib

matplotlib.use("Agg")

from matplotlib.figure import Figure

from tentaclass.datasets import thesis_scanner
from tentaclass.plot.scanner import plot_inspection, save_belt_figure
from tentaclass.scanner import LineScanner, inspect
from tentaclass.scanner.simulate import make_belt, make_objects

d = thesis_scanner()
print(f"{'thesis test grid':<20} {'thesis said':<12} {'now':<10} {'accept':<7} reasons")
for name, grid, said in zip(d.test_names, d.test_grids, d.thesis_answer, strict=True):
    r = inspect(grid)
    print(f"{name:<20} {said or '-':<12} {r.label:<10} {r.accept!s:<7} {'; '.join(r.reasons)}")

# Objects with their expected outline, holes and bites marked.
damaged = make_objects(6, damaged_fraction=1.0, seed=5)
fig = Figure(figsize=(12, 6))
for i, grid in enumerate([d.test_grids[0], d.test_grids[2], *damaged.grids]):
    plot_inspection(grid, ax=fig.add_subplot(2, 4, i + 1))
fig.tight_layout()
fig.savefig("scanner_objects.png", dpi=80)

# A belt streamed in chunks of 16 rows, as a sensor would deliver it.
belt = make_belt(24, width=384, lanes=3, seed=1)
scanner = LineScanner(belt.image.shape[1])
objects = []
for start in range(0, belt.image.shape[0], 16):
    for obj in scanner.feed(belt.image[start : start + 16]):
        objects.append(obj)
objects += scanner.close()
rejected = [o for o in objects if not o.accept]
truth = {tuple(int(v) for v in box): t for box, t in zip(belt.boxes, belt.target, strict=True)}
correct = sum(truth.get(o.bbox) == o.label for o in objects)
print(
    f"belt of {belt.image.shape[0]} lines: {len(objects)} objects, {correct} classified right, "
    f"{len(rejected)} rejected ({int(belt.damaged.sum())} were damaged)"
)
save_belt_figure(belt.image, objects, "scanner_belt.png")
print("wrote scanner_objects.png and scanner_belt.png")
