"""Bins over the sphere of directions for chi-square tests of sampled directions against a pdf: (1 - cos of the
angle to a pole, azimuth about it), the pole being the normal ("n") or the mirror direction of wo ("r"). About the
mirror direction the first coordinate is log(1 - cos): fine bins where a sharp lobe concentrates."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

EPS = 1e-7  # the bins' lower end of 1 - cos(angle to the pole)


def frame(wo: np.ndarray, pole: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The bins' pole (the normal "n", or the mirror direction of wo "r") and two axes perpendicular to it."""
    r = np.array([-wo[0], -wo[1], wo[2]]) if pole == "r" else np.array([0.0, 0.0, 1.0])
    t = np.cross(r, [0.0, 1.0, 0.0])
    t = t / np.linalg.norm(t)
    return r, t, np.cross(r, t)


def to_bins(wi: np.ndarray, fr, log: bool) -> tuple[np.ndarray, np.ndarray]:
    r, t, b = fr
    # 1 - cos = |wi - r|^2 / 2 keeps its digits near the pole, where 1 - dot(wi, r) of float32 directions does not
    one_minus_cos = 0.5 * np.sum((wi - r) ** 2, axis=1)
    a = np.log(one_minus_cos + EPS) if log else one_minus_cos
    phi = np.arctan2(wi @ b, wi @ t) % (2.0 * np.pi)
    return a, phi


def from_bins(a: np.ndarray, phi: np.ndarray, fr, log: bool) -> np.ndarray:
    r, t, b = fr
    c = 1.0 - (np.exp(a) - EPS if log else a)
    s = np.sqrt(np.clip(1.0 - c * c, 0.0, 1.0))
    return (c[:, None] * r + (s * np.cos(phi))[:, None] * t + (s * np.sin(phi))[:, None] * b)


@dataclass
class Bins:
    """n_a x n_p bins about the pole of `pole` for view wo; about the normal the horizon is a bin edge (1 - cos = 1),
    so no bin straddles it."""

    wo: np.ndarray
    pole: str
    n_a: int = 24
    n_p: int = 12
    sphere: bool = False  # about the normal: both hemispheres (1 - cos up to 2), the horizon still a bin edge

    def __post_init__(self) -> None:
        self.frame = frame(self.wo, self.pole)
        self.log = self.pole == "r"
        self.a_edges = (np.linspace(np.log(EPS), np.log(2.0 + EPS), self.n_a + 1) if self.log
                        else np.linspace(0.0, 2.0 if self.sphere else 1.0, self.n_a + 1))
        self.p_edges = np.linspace(0.0, 2.0 * np.pi, self.n_p + 1)

    def probabilities(self, pdf_of: Callable[[np.ndarray], np.ndarray], sub: int = 24) -> np.ndarray:
        """Each bin's probability: pdf_of(directions) integrated over it (sub x sub midpoints per bin)."""
        da = (self.a_edges[1] - self.a_edges[0]) / sub
        dp = (self.p_edges[1] - self.p_edges[0]) / sub
        am = self.a_edges[0] + (np.arange(self.n_a * sub) + 0.5) * da
        pm = (np.arange(self.n_p * sub) + 0.5) * dp
        aa, pp = np.meshgrid(am, pm, indexing="ij")
        pdf = pdf_of(from_bins(aa.ravel(), pp.ravel(), self.frame, self.log))
        # d(omega) = d(1 - cos) d(phi), = exp(a) da dphi in the log bins
        jac = np.exp(aa.ravel()) if self.log else 1.0
        return (pdf * jac * da * dp).reshape(self.n_a, sub, self.n_p, sub).sum(axis=(1, 3))

    def histogram(self, wi: np.ndarray) -> np.ndarray:
        a, phi = to_bins(wi, self.frame, self.log)
        hist, _, _ = np.histogram2d(a, phi, bins=(self.a_edges, self.p_edges))
        return hist
