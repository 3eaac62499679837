"""Polygon clipping in NumPy, the tests' independent reference for the clipping kernels."""

import numpy as np


def clip_polygon(points, value):
    """Sutherland-Hodgman: the part of a planar polygon (a list of points, arrays whose first three entries are
    x, y, z; further entries are carried along linearly) where the linear ``value(point)`` is <= 0."""
    out = []
    for i in range(len(points)):
        a, b = points[i], points[(i + 1) % len(points)]
        fa, fb = value(a), value(b)
        if fa <= 0:
            out.append(a)
        if (fa <= 0) != (fb <= 0):
            out.append(a + fa / (fa - fb) * (b - a))
    return out


def area_and_moment(points):
    """Area and first moment (3,) of a planar polygon (its points' first three entries), fanned from its first."""
    area, moment = 0.0, np.zeros(3)
    for i in range(1, len(points) - 1):
        a, b, c = points[0][:3], points[i][:3], points[i + 1][:3]
        s = 0.5 * np.linalg.norm(np.cross(b - a, c - a))
        area, moment = area + s, moment + s * (a + b + c) / 3
    return area, moment
