"""Write the input files of the geometry examples: ``tube.stl`` (a thick-walled tube in
mm, made with trimesh) and ``concrete.png`` (a synthetic concrete mesostructure:
aggregates as discs, mortar, a few pores). ``part.geo`` is written by hand.

    python examples/geometry/make_inputs.py [--out FOLDER]

The shipped files were made by this script; it needs trimesh (``pip install
"peridynamics[geometry]"``) for the STL and Pillow (with matplotlib) for the PNG.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent

#: the tube: outer and inner radius, height (mm), facets around
TUBE = {"r_out": 10.0, "r_in": 5.0, "height": 30.0, "sections": 48}
#: the image: pixels (W, H), seed, aggregate radii (pixels), grey levels
IMAGE = {"size": (200, 100), "seed": 7, "radii": (6.0, 16.0), "area_fraction": 0.40,
         "aggregate": 200, "mortar": 120, "pore": 10, "pores": 6, "pore_radius": 2.5}  # fmt: skip


def write_tube(path: Path) -> Path:
    """A closed thick-walled tube along z (mm), base at z = 0, as STL."""
    import trimesh

    tube = trimesh.creation.annulus(TUBE["r_in"], TUBE["r_out"], height=TUBE["height"],
                                    sections=TUBE["sections"])  # fmt: skip
    tube.apply_translation([0.0, 0.0, 0.5 * TUBE["height"]])
    assert tube.is_watertight
    tube.export(path)
    return path


def concrete_grey(seed: int = IMAGE["seed"]) -> np.ndarray:
    """Grey image (H, W) uint8: non-overlapping aggregate discs (radii drawn uniformly,
    placed at random, largest first, 1 pixel apart) in mortar, with small pores."""
    rng = np.random.default_rng(seed)
    w, h = IMAGE["size"]
    yy, xx = np.mgrid[0:h, 0:w] + 0.5
    img = np.full((h, w), IMAGE["mortar"], dtype=np.uint8)
    placed: list[tuple[float, float, float]] = []
    area = 0.0
    for r in sorted(rng.uniform(*IMAGE["radii"], size=400), reverse=True):
        for _ in range(200):
            cx, cy = rng.uniform(r + 2, w - r - 2), rng.uniform(r + 2, h - r - 2)
            if all((cx - a) ** 2 + (cy - b) ** 2 > (r + c + 1.0) ** 2 for a, b, c in placed):
                placed.append((cx, cy, r))
                img[(xx - cx) ** 2 + (yy - cy) ** 2 <= r * r] = IMAGE["aggregate"]
                area += np.pi * r * r
                break
        if area >= IMAGE["area_fraction"] * w * h:
            break
    pores = 0
    while pores < IMAGE["pores"]:
        cx, cy = rng.uniform(10, w - 10), rng.uniform(10, h - 10)
        disc = (xx - cx) ** 2 + (yy - cy) ** 2 <= IMAGE["pore_radius"] ** 2
        if np.all(img[disc] == IMAGE["mortar"]):
            img[disc] = IMAGE["pore"]
            pores += 1
    return img


def write_concrete(path: Path) -> Path:
    """The mesostructure as an 8-bit grey PNG."""
    from PIL import Image

    Image.fromarray(concrete_grey(), mode="L").save(path)
    return path


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=HERE)
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    print(write_tube(args.out / "tube.stl"))
    print(write_concrete(args.out / "concrete.png"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
