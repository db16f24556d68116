"""2-D bodies from images (PNG, TIFF: a CT slice of concrete or rock): phases by grey
level become node sets, and a phase may be removed (pores).

The image covers ``W x H`` pixels of side ``pixel_size`` (m), its lower-left corner at
``origin``, the first image row at the top. It is sampled on the cell-centre grid of
spacing dx (``floor(W pixel_size / dx)`` by ``floor(H pixel_size / dx)`` cells, as a
rectangle fits whole cells): each point takes the grey level of the pixel it lies in
(dx = pixel_size: one point per pixel). Grey levels are scaled to [0, 1]: 8-bit images
by 255, 16-bit ones by 65535, colour images through their luminance (Pillow's ``L``
mode), floating-point images as they are. A point belongs to the first phase whose
closed range ``[lo, hi]`` holds its grey level; every point must find one.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from peridynamics.geometry.cloud import Plane, PointCloud


@dataclass(frozen=True)
class Phase:
    """One material phase of an image.

    Attributes
    ----------
    name : str
        Name of its node set.
    lo, hi : float
        Closed grey-level range in [0, 1].
    remove : bool
        True: its points are removed (pores, voids).
    """

    name: str
    lo: float
    hi: float
    remove: bool = False


def read_grey(path: str | Path) -> NDArray[np.float64]:
    """Grey levels of an image in [0, 1], shape (H, W), the first row at the top."""
    from PIL import Image, UnidentifiedImageError

    name = str(path)
    if not Path(path).is_file():
        raise ValueError(f"image file {name!r} does not exist")
    try:
        with Image.open(name) as img:
            img.load()
            mode = img.mode
            if mode.startswith("I;16") or mode == "I":
                data = np.asarray(img, dtype=np.float64) / 65535.0
            elif mode == "F":
                data = np.asarray(img, dtype=np.float64)
            else:
                data = np.asarray(img.convert("L"), dtype=np.float64) / 255.0
    except (UnidentifiedImageError, OSError) as exc:
        raise ValueError(f"cannot read the image {name!r}: {exc}") from None
    if data.ndim != 2 or not np.all(np.isfinite(data)):
        raise ValueError(f"image {name!r}: expected one finite grey channel, got {data.shape}")
    return data


def image_shape(path: str | Path) -> tuple[int, int]:
    """(H, W) pixels of an image, read from its header (no pixel is decoded)."""
    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(str(path)) as img:
            w, h = img.size
    except (UnidentifiedImageError, OSError) as exc:
        raise ValueError(f"cannot read the image {str(path)!r}: {exc}") from None
    return int(h), int(w)


def grid_cells(shape: tuple[int, int], pixel_size: float, spacing: float) -> tuple[int, int]:
    """Grid cells (nx, ny) of spacing dx (m) that fit in the image (whole cells)."""
    h, w = shape
    nx = int(np.floor(w * pixel_size / spacing * (1.0 + 1e-9)))
    ny = int(np.floor(h * pixel_size / spacing * (1.0 + 1e-9)))
    if nx < 1 or ny < 1:
        raise ValueError(
            f"the image is {w * pixel_size:.4g} x {h * pixel_size:.4g} m (pixel_size "
            f"{pixel_size} m): smaller than one grid cell of {spacing} m"
        )
    return nx, ny


def from_image(
    path: str | Path,
    pixel_size: float,
    spacing: float,
    phases: Sequence[Phase],
    origin: tuple[float, float] = (0.0, 0.0),
    thickness: float = 1.0,
    plane: Plane = "stress",
) -> PointCloud:
    """A plate from an image, one node set per kept phase.

    Parameters
    ----------
    path : str or Path
        PNG or TIFF (any format Pillow reads).
    pixel_size : float
        Side of a pixel (m).
    spacing : float
        Grid spacing dx (m).
    phases : sequence of Phase
        Grey-level ranges in [0, 1], the first match wins.
    origin : (2,) float
        Lower-left corner of the image (m).
    thickness : float
        Plate thickness (m): volume dx^2 x thickness.
    plane : {"stress", "strain"}
        2-D idealisation.

    Returns
    -------
    PointCloud
        Points (n, 2) (m) of the kept phases with node sets named after them.
    """
    grey = read_grey(path)
    h, w = grey.shape
    nx, ny = grid_cells((h, w), pixel_size, spacing)
    xc = (np.arange(nx) + 0.5) * spacing
    yc = (np.arange(ny) + 0.5) * spacing
    col = np.minimum((xc / pixel_size).astype(np.intp), w - 1)
    row = h - 1 - np.minimum((yc / pixel_size).astype(np.intp), h - 1)
    g = grey[row[None, :], col[:, None]].reshape(-1)  # x slowest, as the rectangle's grid
    x = np.stack(np.meshgrid(xc, yc, indexing="ij"), -1).reshape(-1, 2) + np.asarray(origin)
    phase = np.full(len(g), -1, dtype=np.intp)
    for k, ph in enumerate(phases):
        phase[(phase < 0) & (g >= ph.lo) & (g <= ph.hi)] = k
    if np.any(phase < 0):
        left = g[phase < 0]
        raise ValueError(
            f"{int(left.size)} points of image {str(path)!r} have grey levels "
            f"{left.min():.4g} .. {left.max():.4g} in no phase's range; widen a phase's "
            "grey range (levels are scaled to 0 .. 1)"
        )
    keep = ~np.isin(phase, [k for k, ph in enumerate(phases) if ph.remove])
    if not keep.any():
        raise ValueError(f"the removed phases take every point of image {str(path)!r}")
    x, phase = x[keep], phase[keep]
    sets = {ph.name: np.flatnonzero(phase == k) for k, ph in enumerate(phases) if not ph.remove}
    vol = np.full(len(x), spacing * spacing * thickness)
    return PointCloud(x=x, volume=vol, spacing=spacing, cross_section=thickness, plane=plane,
                      node_sets=sets)  # fmt: skip
