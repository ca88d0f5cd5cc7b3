"""Pixel checks for rendered pictures (player screenshots, video frames)."""

from __future__ import annotations

import colorsys
import io

import numpy as np

from legdsl.export.shapes import hex_rgb


def pixels(png: bytes) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(float) / 255


def hue_mask(image: np.ndarray, color: str, tolerance: float = 0.06) -> np.ndarray:
    """Pixels whose hue is within ``tolerance`` (of a turn) of ``color``'s and that are clearly coloured."""
    target = colorsys.rgb_to_hsv(*hex_rgb(color))[0]
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    high, low = image.max(axis=2), image.min(axis=2)
    chroma = high - low
    with np.errstate(invalid="ignore", divide="ignore"):
        h = (
            np.where(
                high == r,
                ((g - b) / chroma) % 6,
                np.where(high == g, (b - r) / chroma + 2, (r - g) / chroma + 4),
            )
            / 6
        )
    distance = np.minimum(np.abs(h - target), 1 - np.abs(h - target))
    return (chroma > 0.12) & (distance < tolerance)
