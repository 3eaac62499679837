r"""O'Brien–Hodgins height field: columns joined to 8 neighbours by virtual pipes.

Where the arrays live
---------------------
The grid has ``nx × ny`` columns of side :math:`l` (``spacing``), column
``(i, j)`` centred at ``(x0 + i l, y0 + j l)``. Column arrays (heights,
external pressure) have shape ``(nx, ny)``. Each pipe joins two columns and
carries a volume flow :math:`Q` [m³/s], positive from the first column to the
second; there is one array per pipe direction:

=========  ===============  =================================
field      shape            joins
=========  ===============  =================================
``qx``     ``(nx-1, ny)``   ``(i, j) → (i+1, j)``
``qy``     ``(nx, ny-1)``   ``(i, j) → (i, j+1)``
``qd``     ``(nx-1, ny-1)`` ``(i, j) → (i+1, j+1)``
``qa``     ``(nx-1, ny-1)`` ``(i, j+1) → (i+1, j)``
=========  ===============  =================================

A flow leaves one column and enters the other, so the total volume is
conserved exactly by construction (closed boundaries: no pipe leaves the grid).

Equations
---------
The pressure at a column's base is :math:`P = \rho g h + p_\mathrm{ext}`. A
pipe of cross-section :math:`c` and length :math:`L` accelerates its flow
with the pressure difference (physics.md §2),

.. math:: \dot Q = \frac{c}{\rho L}\,(P_a - P_b), \qquad
          l^2\,\dot h_{ij} = -\sum_{\text{pipes of } ij} Q_\text{out},

with :math:`L = l` on the axes and :math:`\sqrt2\,l` on the diagonals.
Linearised about the rest depth :math:`H` this is the wave equation with a
9-point Laplacian; choosing the cross-sections

.. math:: c_\text{axis} = \tfrac23\, l H, \qquad c_\text{diag} = \tfrac{\sqrt2}{6}\, l H

makes that Laplacian the isotropic one, :math:`\frac{1}{6l^2}(4\sum_\text{axis} +
\sum_\text{diag} - 20\,h)`, so small waves travel at :math:`\sqrt{gH}` along
the axes *and* the diagonals. (Equal cross-sections :math:`lH` on all eight
pipes would give waves :math:`\sqrt{1+\sqrt2}` too fast.)

Time stepping and its bound
---------------------------
Semi-implicit (symplectic) Euler: flows first, from the current heights, then
heights from the new flows, :math:`h \mathrel{-}= \Delta t\,\mathrm{div}\,Q/l^2`.
O'Brien and Hodgins average the old and new flows in the height update; for the
undamped linear scheme that map has determinant :math:`1 + (\omega\Delta t)^2/2 > 1`
per mode and slowly amplifies every wave, while symplectic Euler has
determinant 1 and is stable for :math:`\omega_\max \Delta t \le 2`. The
stiffest mode of the isotropic stencil is the checkerboard, with
:math:`\omega_\max^2 = \tfrac{16}{3}\, gH/l^2`, hence the bound

.. math:: \Delta t \le \Delta t_\max = \frac{\sqrt3}{2}\,\frac{l}{\sqrt{gH}} \approx 0.866\,\frac{l}{\sqrt{gH}}

(:func:`stable_dt`). At the bound itself the modes of a closed grid stay bounded (its edges keep
the stiffest mode just below the endless checkerboard's frequency), but modes near it swing to many
times their start: a 16 × 16 checkerboard of 1 µm peaked at 34 µm at the bound over :math:`10^5`
steps (28–32 µm read every 1000 steps, the test's sampling) without growing further, against 4.7 µm
(3 µm every 1000 steps) at the default ``cfl`` of 0.5 (tested; measured 2026-12-06 by a review). The swing
grows with the grid: 25 / 124 / 459 µm on closed 16² / 64² / 256² grids at the bound (the last over 5000 steps),
and random noise grew 7 / 10 / 13× (a review, stop 48); 1.001× the bound already grows on 64² and 256² grids
until the clamp holds it near the depth. The pipes'
cross-sections use the rest depth :math:`H` (the scheme is linear in the heights), so the bound holds
whatever the local depth; :class:`WaterGrid` holds ``dt`` to
``cfl`` (default 0.5) of the bound at the rest depth and refuses a ``dt`` beyond
the bound; :func:`water_substeps` gives the substeps that keep a longer interval
within it. The pure step of :func:`make_water_step` takes ``dt`` as a traced value
and cannot check it: its callers keep it within ``grid.time_step`` (the coupled
stone substeps, :mod:`jaxskip.coupled`).

Keeping columns non-negative (the clamp)
----------------------------------------
Where a column would lose more than it holds, its outflows are scaled back by a
factor :math:`s \in [0, 1]` per column (the source column's factor scales a
pipe's flow, so volume stays conserved). Three variants (``clamp=``):

``"reference"``
    The original scale-back, iterated (the seed paper's eq. 3): a column whose
    outflow exceeds its volume plus inflow gets :math:`s = \min(1, (V + \text{in})/\text{out})`.
    Scaling one column changes its neighbours' inflows, so the test is repeated
    (``clamp_iterations`` passes). We start from the inflow-free factors
    :math:`\min(1, V/\text{out})`, which are safe whatever the neighbours do,
    and relax upwards; each pass only raises factors and so only raises inflows,
    hence *every* pass keeps all columns non-negative and more passes only remove
    needless scaling. Conserves volume exactly. Where flow runs through chains of nearly dry
    columns the default 4 passes still over-scale: on random flows over a 16 × 16 grid with many
    dry columns the largest flow differs from the 100-pass answer by 0.35 of the largest flow
    (8 passes: 0.068, 16: 1e-3, 32: 2.5e-7); under a stone-like Gaussian push 4 and 100 passes
    agree to the bit (measured in session 23).
``"zero"``
    The seed's cheap version (eq. 4): a column that would go negative is set to
    zero. Adds volume, and not a little: the equation zeroes the column, not its
    pipes, so an emptied column keeps draining and every step adds its outflow
    back. A closed 32 × 32 grid 2 cm deep, pushed by a 1.5 cm wide Gaussian for 30
    steps and left for 400, gains 11 / 163 / 703 % of its volume at 0.3 / 1 / 3 kPa
    (the reference: 1e-16). At the scheme's stable bound on a drying grid it blows up:
    a closed 16 × 16 grid 10 cm deep, started as a checkerboard of ±9 cm, grows its
    tallest column to ~1e9 times the depth (5.5e8 times its first tallest) and its volume 5.5e8-5.7e8-fold in
    20 000 steps at the bound (session 27; re-run by a review, 2026-12-07) (+27 % at the default ``cfl`` 0.5;
    the reference and smooth clamps keep it to rounding). Kept as the paper's baseline.
``"smooth"``
    The reference with :math:`\min(1, r)` replaced by the generalised mean
    :math:`(1 + r^{-k})^{-1/k}` (``sharpness`` :math:`k`), a smooth lower bound
    of :math:`\min(1, r)` that tends to it as :math:`k \to \infty`. Being a lower
    bound, it scales at least as much as the reference: volume conserved,
    columns non-negative, and differentiable everywhere. Away from drying
    (:math:`r \gg 1`) it departs from 1 by :math:`r^{-k}/k`.

Boundaries
----------
``"closed"``: no pipe leaves the grid; waves reflect. ``"sponge"``: a border
of ``sponge_width`` columns where heights relax to the rest depth and flows to
zero at a rate rising quadratically to ``sponge_rate`` [1/s] at the edge, so
waves leave instead of coming back (volume is then not conserved: waves carry
it out). Both relaxations are implicit: a pipe's flow update becomes
:math:`Q \leftarrow (Q + \Delta t\,\dot Q)/(1 + \Delta t\,r)` (like ``damping``), so the
clamp and the heights see the relaxed flows, and after the height update a column's
excess over the rest depth is divided by :math:`1 + \Delta t\,r`. (Until 2026-12-06 the
flows were relaxed after the heights had moved with the unrelaxed ones: the same flows
in the state to rounding where the clamp does not bite, other heights in the border, and XLA
copied all five state arrays every step to do it.)

Example
-------
>>> import jax.numpy as jnp
>>> grid = WaterGrid(shape=(32, 32), spacing=0.02, depth=0.05)
>>> state = still_water(grid)
>>> step = make_water_step(grid)
>>> state = step(state, jnp.zeros(grid.shape))
>>> float(jnp.max(jnp.abs(state.height - grid.depth))) == 0.0     # still water stays still
True
"""

from __future__ import annotations

import dataclasses
import functools
import math
import numbers
import time

import jax
import jax.numpy as jnp
import numpy as np

from ._docs import document_fields
from ._checks import ParameterError, check_bool, check_choice, check_int, check_positive, check_range, check_real
from .forces import GRAVITY_RANGE, RHO_RANGE

CLAMPS = ("reference", "zero", "smooth")
BOUNDARIES = ("closed", "sponge")
MAX_COLUMNS = 4096 * 4096
#: Accepted column spacing [m] and depth [m]. A denormal spacing (1e-300) passed a check of > 0 and
#: raised a bare ZeroDivisionError; a denormal gravity gave NaN heights.
SPACING_RANGE = (1e-5, 1e3)
DEPTH_RANGE = (1e-5, 1e4)
_MARGIN = 1e-9   # relative: a column drained by the clamp keeps ~1e-9 of its outflow, above round-off


def _margin(dtype) -> float:
    """The clamp's relative margin for ``dtype``: :data:`_MARGIN`, or 64 units of round-off where that is
    more (float32: 1 + 1e-9 rounds to 1, and drained columns dipped to -2e-9 m; 64 units keep the smooth
    clamp's log-exp factor below its bound too)."""
    return max(_MARGIN, 64.0 * float(jnp.finfo(dtype).eps))


@document_fields
@dataclasses.dataclass(frozen=True)
class WaterGrid:
    """Static (hashable) description of a height-field grid. SI units.

    Every field is static: it fixes the compiled step, so none can be traced or differentiated (a gradient with
    respect to the depth or the damping is not available), and each new value compiles its own program (a
    cache of 32 grids). Vary them in Python."""

    shape: tuple[int, int] = (128, 128)
    """Columns ``(nx, ny)``, each at least 3, at most 4096² in all (integers; NumPy's too)."""
    spacing: float = 0.01
    """Column side :math:`l` [m] (also the axis pipe length), in [1e-5, 1e3]."""
    depth: float = 0.1
    """Rest depth :math:`H` [m], in [1e-5, 1e4]: waves travel at :math:`\\sqrt{gH}`."""
    origin: tuple[float, float] = (0.0, 0.0)
    """Centre ``(x, y)`` [m] of column ``(0, 0)`` (a list of two is stored as a tuple)."""
    gravity: float = 9.81
    """Gravitational acceleration g [m/s²], in [0.01, 100]."""
    rho: float = 1000.0
    """Water density ρ [kg/m³], in [10, 20000] (converts external pressure to head)."""
    dt: float | None = None
    """Water time step [s], in (0, :func:`stable_dt`]; ``None``: ``cfl`` times :func:`stable_dt`."""
    cfl: float = 0.5
    """Fraction of the stability bound used when ``dt`` is None [-], in (0, 1]."""
    clamp: str = "reference"
    """Non-negative volume clamp: ``"reference"``, ``"zero"`` or ``"smooth"``."""
    sharpness: float = 50.0
    """Exponent k of the smooth clamp [-], in [1, 10^6] (larger: closer to the reference)."""
    clamp_iterations: int = 4
    """Relaxation passes of the reference and smooth clamps, in [0, 100] (each pass is safe; more: less
    over-scaling)."""
    damping: float = 0.0
    """Linear damping rate of pipe flows [1/s], in [0, 10^6] (0: none)."""
    boundary: str = "closed"
    """``"closed"`` (reflecting) or ``"sponge"`` (absorbing border)."""
    sponge_width: int = 8
    """Sponge border width [columns], in [1, 10^4] (``boundary="sponge"``; at most half the smaller side)."""
    sponge_rate: float = 50.0
    """Relaxation rate at the outer edge of the sponge [1/s], > 0."""

    def __post_init__(self):
        shape = self.shape
        if (not isinstance(shape, (tuple, list)) or len(shape) != 2
                or not all(isinstance(n, numbers.Integral) and not isinstance(n, (bool, np.bool_)) for n in shape)):
            raise ParameterError(f"shape must be a tuple of two integers (nx, ny), got {shape!r}")
        shape = (int(shape[0]), int(shape[1]))
        object.__setattr__(self, "shape", shape)  # plain ints: hashable and equal to the same grid given as ints
        if min(shape) < 3:
            raise ParameterError(f"shape must have at least 3 columns per side, got {shape}")
        if shape[0] * shape[1] > MAX_COLUMNS:
            raise ParameterError(f"shape {shape} has {shape[0] * shape[1]} columns; at most {MAX_COLUMNS} "
                                 f"(4096 x 4096) are allowed: use a window that follows the stone")
        # Every number is stored as the plain float it was checked as (a NumPy or JAX scalar would
        # otherwise ride along into the hash and the compiled steps).
        put = lambda name, v: object.__setattr__(self, name, v)  # noqa: E731
        put("spacing", check_range("spacing", self.spacing, *SPACING_RANGE, unit="m"))
        put("depth", check_range("depth", self.depth, *DEPTH_RANGE, unit="m"))
        if not (isinstance(self.origin, (tuple, list)) and len(self.origin) == 2):   # (stored as a tuple: hashable)
            raise ParameterError(f"origin must be a tuple (x, y) in m, got {self.origin!r}")
        put("origin", tuple(check_real(name, v, unit="m") for name, v in zip(("origin[0]", "origin[1]"), self.origin)))
        put("gravity", check_range("gravity", self.gravity, *GRAVITY_RANGE, unit="m/s^2"))
        put("rho", check_range("rho", self.rho, *RHO_RANGE, unit="kg/m^3"))
        put("cfl", check_range("cfl", self.cfl, 0.0, 1.0, low_open=True))
        if self.dt is not None:
            put("dt", check_positive("dt", self.dt, unit="s"))
            bound = stable_dt(self.spacing, self.depth, self.gravity)
            if self.dt > bound:
                raise ParameterError(
                    f"dt must be in (0, {bound:.6g}] s for spacing {self.spacing} m and depth {self.depth} m "
                    f"(the pipe scheme's bound sqrt(3)/2 * spacing / sqrt(g * depth)), got {self.dt}; "
                    f"use a smaller dt, or substeps via water_substeps()")
        check_choice("clamp", self.clamp, CLAMPS)
        put("sharpness", check_range("sharpness", self.sharpness, 1.0, 1e6))
        put("clamp_iterations", check_int("clamp_iterations", self.clamp_iterations, minimum=0, maximum=100))
        put("damping", check_range("damping", self.damping, 0.0, 1e6))
        check_choice("boundary", self.boundary, BOUNDARIES)
        put("sponge_width", check_int("sponge_width", self.sponge_width, minimum=1, maximum=10_000))
        put("sponge_rate", check_positive("sponge_rate", self.sponge_rate, unit="1/s"))
        if self.boundary == "sponge" and self.sponge_width > min(shape) // 2:
            raise ParameterError(f"sponge_width must be at most half the smaller grid side "
                                 f"({min(shape) // 2} columns for shape {shape}), got {self.sponge_width}")

    @property
    def time_step(self) -> float:
        """The water time step [s] in use."""
        if self.dt is not None:
            return float(self.dt)
        return self.cfl * stable_dt(self.spacing, self.depth, self.gravity)

    @property
    def wave_speed(self) -> float:
        """Shallow-water wave speed :math:`\\sqrt{gH}` [m/s]."""
        return math.sqrt(self.gravity * self.depth)

    def column_centres(self):
        """Column centre coordinates ``(x, y)`` [m], each of shape ``(nx, ny)``."""
        nx, ny = self.shape
        x = self.origin[0] + self.spacing * jnp.arange(nx)
        y = self.origin[1] + self.spacing * jnp.arange(ny)
        return jnp.meshgrid(x, y, indexing="ij")


def stable_dt(spacing: float, depth: float, gravity: float = 9.81) -> float:
    """Largest stable time step [s] of the pipe scheme: :math:`\\frac{\\sqrt3}{2} l/\\sqrt{gH}`, for a
    column ``spacing`` l [m], a ``depth`` H [m] and ``gravity`` g [m/s^2].

    >>> round(stable_dt(0.01, 0.1), 6)
    0.008744
    """
    check_range("spacing", spacing, *SPACING_RANGE, unit="m")
    check_range("depth", depth, *DEPTH_RANGE, unit="m")
    check_range("gravity", gravity, *GRAVITY_RANGE, unit="m/s^2")
    return math.sqrt(3.0) / 2.0 * spacing / math.sqrt(gravity * depth)


def _check_grid(grid) -> WaterGrid:
    """``grid`` must be a :class:`WaterGrid` (a clear error instead of an AttributeError deep inside)."""
    if not isinstance(grid, WaterGrid):
        raise ParameterError(f"grid must be a jaxskip.WaterGrid (e.g. WaterGrid(shape=(128, 128), spacing=0.01)), "
                             f"got {type(grid).__name__}")
    return grid


def water_substeps(grid: WaterGrid, dt: float) -> int:
    """Water steps per stone step of ``dt`` [s] so each water step is within the bound: an integer in
    [1, 10^8] (a longer ``dt`` is refused, naming the most it may be: 1e300 s gave a 303-digit count)."""
    _check_grid(grid)
    check_positive("dt", dt, unit="s")
    n = max(1, math.ceil(dt / grid.time_step - 1e-12))
    if n > MAX_SUBSTEPS:
        raise ParameterError(f"dt must be at most {MAX_SUBSTEPS * grid.time_step:.6g} s ({MAX_SUBSTEPS:.0e} water steps of "
                             f"{grid.time_step:.6g} s), got {dt!r}")
    return n


#: Most water steps :func:`water_substeps` gives for one stone step.
MAX_SUBSTEPS = 100_000_000


@document_fields
@jax.tree_util.register_dataclass
@dataclasses.dataclass(frozen=True)
class WaterState:
    """Height field state (a pytree; add leading axes for a batch)."""

    height: jax.Array
    """Column water heights h [m] above the bed, at column centres, shape ``(nx, ny)``; rest: ``depth``."""
    qx: jax.Array
    """Flows [m³/s] in the x pipes, ``(i, j) → (i+1, j)``, shape ``(nx-1, ny)``."""
    qy: jax.Array
    """Flows [m³/s] in the y pipes, ``(i, j) → (i, j+1)``, shape ``(nx, ny-1)``."""
    qd: jax.Array
    """Flows [m³/s] in the diagonal pipes ``(i, j) → (i+1, j+1)``, shape ``(nx-1, ny-1)``."""
    qa: jax.Array
    """Flows [m³/s] in the anti-diagonal pipes ``(i, j+1) → (i+1, j)``, shape ``(nx-1, ny-1)``."""
    time: jax.Array
    """Simulated time [s], scalar."""


def still_water(grid: WaterGrid, height=None, dtype=None) -> WaterState:
    """Water at rest: all flows zero; heights ``depth`` (or the given ``(nx, ny)`` array of column heights
    [m], finite and >= 0).

    ``dtype``: float32 or float64 for every array of the state (``jnp.float32``, ``"float64"``; half
    precisions are refused: their clock stops); default: JAX's default float (float32, or float64 with
    ``jax_enable_x64``), or ``height``'s own if it is float32 or float64 (integer heights become floats).
    """
    _check_grid(grid)
    if dtype is not None:
        try:
            floating = jnp.issubdtype(jnp.dtype(dtype), jnp.floating)
        except TypeError:
            floating = False
        if not floating:
            raise ParameterError(f"dtype must be a floating-point dtype (e.g. jnp.float32 or jnp.float64), got {dtype!r}")
        if jnp.finfo(jnp.dtype(dtype)).bits < 32:  # (bfloat16's clock stopped at 2 s; the volume drifted 4e-3)
            raise ParameterError(f"dtype must be float32 or float64: {jnp.dtype(dtype).name} cannot hold the clock "
                                 f"or the volume (time stops advancing), got {dtype!r}")
    nx, ny = grid.shape
    if height is None:
        height = jnp.full(grid.shape, grid.depth, dtype=dtype or jnp.result_type(float))
    elif not isinstance(height, jax.core.Tracer):
        raw = np.asarray(height) if not isinstance(height, str) else None
        if raw is None or raw.dtype.kind not in "iuf":   # not text, True/False or complex numbers
            raise ParameterError(f"height must be an (nx, ny) array of real column heights [m], got "
                                 f"{type(height).__name__}{'' if raw is None else f' of dtype {raw.dtype}'}")
        if raw.shape == grid.shape:
            _check_heights("height", raw)
        if raw.dtype.kind in "iu" or (dtype is None and raw.dtype.itemsize < 4):   # whole metres: still a float
            height = raw.astype(jnp.result_type(float))
    height = jnp.asarray(height, dtype=dtype)
    if height.shape != grid.shape:
        raise ParameterError(f"height must have the grid's shape {grid.shape}, got {height.shape}")
    z = lambda *s: jnp.zeros(s, height.dtype)
    return WaterState(height=height, qx=z(nx - 1, ny), qy=z(nx, ny - 1), qd=z(nx - 1, ny - 1),
                      qa=z(nx - 1, ny - 1), time=jnp.zeros((), height.dtype))


def _gather_out(qx, qy, qd, qa):
    """Per column: the flow out through each of its 8 pipes, as a tuple of 8 ``(nx, ny)`` arrays.

    A pipe's flow counts positive out of its first column and negative out of its second.
    """
    px = lambda a, lo, hi: jnp.pad(a, ((lo, hi), (0, 0)))
    py = lambda a, lo, hi: jnp.pad(a, ((0, 0), (lo, hi)))
    pxy = lambda a, x, y: jnp.pad(a, (x, y))
    return (px(qx, 0, 1), -px(qx, 1, 0),            # to +x, to -x
            py(qy, 0, 1), -py(qy, 1, 0),            # to +y, to -y
            pxy(qd, (0, 1), (0, 1)), -pxy(qd, (1, 0), (1, 0)),   # to (+1,+1), to (-1,-1)
            pxy(qa, (0, 1), (1, 0)), -pxy(qa, (1, 0), (0, 1)))   # from (i, j+1) to (+1, -1); reverse


def _net_out(qx, qy, qd, qa):
    """Net volume flow out of each column [m³/s], ``(nx, ny)``."""
    return sum(_gather_out(qx, qy, qd, qa))


def _outflow(parts):
    """Per column: total outgoing flow [m³/s] (≥ 0) of :func:`_gather_out`'s 8 parts."""
    return sum(jnp.maximum(p, 0.0) for p in parts)


def _scale_pipes(qx, qy, qd, qa, s):
    """Scale each pipe's flow by the factor of the column it leaves (``s`` at column centres)."""
    def by_source(q, s_first, s_second):
        return jnp.where(q > 0, q * s_first, q * s_second)
    return (by_source(qx, s[:-1, :], s[1:, :]), by_source(qy, s[:, :-1], s[:, 1:]),
            by_source(qd, s[:-1, :-1], s[1:, 1:]), by_source(qa, s[:-1, 1:], s[1:, :-1]))


@jax.custom_jvp
def _capped_ratio(a, o):
    """min(1, a/o) for a, o > 0, with the derivative written as (da - r do)/o: JAX's rule for a
    division forms a/o² for the denominator, which overflows for a tiny outflow o (below ~1e-154 m³
    in float64, ~5e-20 m³ in float32, near drained columns) and gave NaN (inf times a zero
    cotangent) where the factor was 1."""
    return jnp.minimum(1.0, a / o)


@_capped_ratio.defjvp
def _capped_ratio_jvp(primals, tangents):
    (a, o), (da, do) = primals, tangents
    r = _capped_ratio(a, o)
    return r, jnp.where(a < o, (da - r * do) / o, 0.0 * da)


@jax.custom_jvp
def _log_ratio(a, o):
    """log(a/o) for a, o > 0; derivative da/a - do/o (a cotangent is divided, never multiplied by an
    overflowing 1/o², as by JAX's rule for the division)."""
    return jnp.log(a / o)


@_log_ratio.defjvp
def _log_ratio_jvp(primals, tangents):
    (a, o), (da, do) = primals, tangents
    return _log_ratio(a, o), da / a - do / o


def _ratio_factor(avail, out, smooth: bool, k: float):
    """Outflow factor s = min(1, avail/out) (or its smooth lower bound), per column.

    Double-where: columns with no outflow, or nothing available, never take
    a log or a division of zero; and the ratio's derivative is formed without 1/out², so
    gradients stay finite for tiny outflows too.
    """
    has_out = out > 0
    has_avail = avail > 0
    safe_out = jnp.where(has_out, out, 1.0)
    safe_avail = jnp.where(has_avail, avail, 1.0)
    if smooth:
        log_r = _log_ratio(safe_avail, safe_out)
        s = jnp.exp(-jax.nn.softplus(-k * log_r) / k)   # (1 + r^-k)^(-1/k) <= min(1, r)
    else:
        s = _capped_ratio(safe_avail, safe_out)
    s = jnp.where(has_avail, s, 0.0)
    return jnp.where(has_out, s, 1.0)


# The 8 neighbours of column (i, j), as offsets (di, dj), in the order of _gather_out's parts:
# the neighbour that part's pipe leads to.
_NEIGHBOURS = ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, -1), (1, -1), (-1, 1))


def _inflow(incoming, s, pad=0.0):
    """Per column: inflow [m³/s] when every column's outflows are scaled by its factor ``s``.

    ``incoming``: 8 ``(nx, ny)`` arrays at column centres, the flow (≥ 0) arriving at
    column (i, j) from its neighbour (i + di, j + dj) (:data:`_NEIGHBOURS` order),
    unscaled. The neighbours' factors are read from one padded copy of ``s`` by
    plain slices, so each pass is two fused loops over the grid (a formulation with
    a pad per pipe direction cost ~8x more on CPU: 8 kernels per pass).
    """
    nx, ny = s.shape
    sp = jax.lax.optimization_barrier(jnp.pad(s, 1, constant_values=pad))
    return sum(a * sp[1 + di:1 + di + nx, 1 + dj:1 + dj + ny] for a, (di, dj) in zip(incoming, _NEIGHBOURS))


CLAMP_LIST = 64
"""At most this many columns at risk: a block's clamp passes run on them alone (:func:`_clamp`'s
``listed``); more, and they run on every column of the block."""


def _risk_margin(grid: WaterGrid) -> float:
    """A column is at risk (its clamp factor can differ from 1 by more than round-off) when
    ``margin * dt * out >= volume``. The smooth factors differ from 1 by about r^-k/k with
    r = V/out; this margin keeps that below 1e-16 (every column holding ~1.9x its outflow at k = 50)."""
    return (1e-16 * grid.sharpness) ** (-1.0 / grid.sharpness) if grid.clamp == "smooth" else 1.0


def _clamp(grid: WaterGrid, volume, flows, dt, block=None, listed: bool = False):
    """Scale outflows so no column goes below zero (reference and smooth clamps).

    Starts from the inflow-free factors min(1, V/out), which are safe whatever
    the neighbours do, and relaxes upwards: s <- min(1, (V + in(s))/out). Each
    pass only raises factors, and raising a factor only raises its neighbours'
    inflows, so every pass stays safe while the factors climb to a fixed point
    of the paper's test (outflow cut only as far as volume plus inflow requires).

    ``block = (i0, j0, bx, by)`` (``i0, j0`` may be traced, ``bx, by`` static):
    compute the factors only for the columns ``[i0:i0+bx, j0:j0+by]``; every other
    column keeps factor 1. Valid when no column outside the block is at risk (the
    caller checks). The block must keep one column from the grid's edge
    (``1 <= i0``, ``i0 + bx <= nx - 1``, the same along y): the work is then done on
    the block and its one-column ring alone — the pipes of that ring are cut out of
    the flows, scaled and written back in place — and costs the block, not the grid.

    ``listed=True`` (with a block; valid when at most :data:`CLAMP_LIST` columns are at
    risk, the caller checks): the passes run on the columns at risk alone, gathered
    into a list, and every other column keeps factor 1 exactly (a column not at risk
    has a factor within round-off of 1 whatever its neighbours do: inflows only raise
    it). The same answer to round-off; the passes cost the list, not the block.
    """
    smooth = grid.clamp == "smooth"
    k = float(grid.sharpness)
    if block is not None:
        i0, j0, bx, by = block
        corner = (i0 - 1, j0 - 1)       # the ring's first column
        cut = lambda q, shape: jax.lax.dynamic_slice(q, corner, shape)  # noqa: E731
        # The pipes of the (bx + 2) x (by + 2) columns of the block and its ring, between them.
        sub = (cut(flows[0], (bx + 1, by + 2)), cut(flows[1], (bx + 2, by + 1)),
               cut(flows[2], (bx + 1, by + 1)), cut(flows[3], (bx + 1, by + 1)))
        # Exact for the block's columns (all their pipes are in ``sub``); the ring's are not used.
        parts = tuple(p[1:-1, 1:-1] for p in _gather_out(*sub))
        volume = jax.lax.dynamic_slice(volume, (i0, j0), (bx, by))
    else:
        parts = _gather_out(*flows)    # flow out of (i, j) towards each neighbour (negative: in)
    out = _outflow(parts)
    incoming = tuple(jnp.maximum(-p, 0.0) for p in parts)
    need = dt * out * (1.0 + _margin(out.dtype))   # aim a hair above zero: round-off cannot dip below
    if block is not None and listed:
        s = _listed_factors(grid, volume, out, need, incoming, dt)
    else:
        s = _ratio_factor(volume, need, smooth, k)
        for _ in range(grid.clamp_iterations):
            s = _ratio_factor(volume + dt * _inflow(incoming, s, 1.0 if block is not None else 0.0), need, smooth, k)
    if block is None:
        return _scale_pipes(*flows, s)
    scaled = _scale_pipes(*sub, jnp.pad(s, 1, constant_values=1.0))   # the ring keeps factor 1
    return tuple(jax.lax.dynamic_update_slice(q, q_sub, corner) for q, q_sub in zip(flows, scaled))


def _listed_factors(grid: WaterGrid, volume, out, need, incoming, dt):
    """:func:`_clamp`'s factors on a block ``(bx, by)``, computed for its columns at risk alone.

    The columns at risk (at most :data:`CLAMP_LIST`) are listed in row-major order
    (a running count over the block and a binary search: no scatter, so XLA:CPU can
    still compile a loop around the step into one function); each one's neighbours are
    found in a map of list slots. The passes are those of :func:`_clamp`, in the same
    order, with factor 1 for every column not listed. Returns the ``(bx, by)`` factors.
    """
    smooth, k, cap = grid.clamp == "smooth", float(grid.sharpness), CLAMP_LIST
    bx, by = volume.shape
    risk = (_risk_margin(grid) * dt * out >= volume).ravel()
    count = jnp.cumsum(risk.astype(jnp.int32))
    pos = jnp.minimum(jnp.searchsorted(count, jnp.arange(1, cap + 1, dtype=count.dtype), side="left"), bx * by - 1)
    valid = jnp.arange(cap) < count[-1]
    slots = jnp.where(risk, count - 1, cap).reshape(bx, by)     # cap: not listed (factor 1)
    ring = jnp.pad(slots, 1, constant_values=cap)
    i, j = pos // by, pos % by
    take = lambda a: a.ravel()[pos]  # noqa: E731
    vol, nd, inc = take(volume), take(need), tuple(take(a) for a in incoming)
    nbr = tuple(ring[1 + i + di, 1 + j + dj] for di, dj in _NEIGHBOURS)
    one = jnp.ones((1,), volume.dtype)
    s = jnp.where(valid, _ratio_factor(vol, nd, smooth, k), 1.0)
    for _ in range(grid.clamp_iterations):
        s1 = jnp.concatenate([s, one])
        inflow = sum(a * s1[n] for a, n in zip(inc, nbr))
        s = jnp.where(valid, _ratio_factor(vol + dt * inflow, nd, smooth, k), 1.0)
    return jnp.concatenate([s, one])[slots]


def _sponge_ramp(grid: WaterGrid, n: int):
    """(n,) sponge ramp along one axis: 0 inside, rising linearly to 1 at the edge columns."""
    w = grid.sponge_width
    i = jnp.arange(n)
    d = jnp.minimum(i, n - 1 - i)             # columns from the nearest edge
    return jnp.clip((w - d) / w, 0.0, 1.0)


def _sponge_keep(grid: WaterGrid, dt):
    """The sponge's factors for a step of ``dt``: ``(column (nx, ny), (x, y, diagonal, anti-diagonal) pipes)``.

    A column keeps ``1 / (1 + dt * rate)`` (implicit relaxation towards rest: 0 inside, rising
    quadratically to ``sponge_rate`` at the edge), a pipe the smaller factor of its two columns.
    The rate is ``sponge_rate * max(rx_i, ry_j)^2`` with one ramp per axis, and both maps are
    monotone, so every factor is the smaller of one per row and one per column: ``nx + ny``
    divisions a step instead of one per column (or two per pipe) — the same numbers, bit for bit.
    """
    nx, ny = grid.shape
    dtype = jnp.result_type(dt)   # (the state's: a float64 ramp turned a float32 state's flows float64 under x64)
    kx = (1.0 / (1.0 + dt * (grid.sponge_rate * _sponge_ramp(grid, nx) ** 2))).astype(dtype)
    ky = (1.0 / (1.0 + dt * (grid.sponge_rate * _sponge_ramp(grid, ny) ** 2))).astype(dtype)
    col = jnp.minimum(kx[:, None], ky[None, :])
    px, py = jnp.minimum(kx[:-1], kx[1:]), jnp.minimum(ky[:-1], ky[1:])
    diagonal = jnp.minimum(px[:, None], py[None, :])    # both diagonals join the same 2 x 2 columns
    return col, (jnp.minimum(px[:, None], ky[None, :]), jnp.minimum(kx[:, None], py[None, :]), diagonal, diagonal)


def make_water_step(grid: WaterGrid, clamp_blocks: tuple = ()):
    """Return the pure step ``step(state, pressure, dt=None) -> state`` for this grid.

    ``pressure``: external pressure on each column [Pa], shape ``(nx, ny)``
    (e.g. from the stone), added to the hydrostatic :math:`\\rho g h`. One call
    advances ``dt`` seconds (a scalar, may be traced; default ``grid.time_step``).
    A concrete ``dt`` outside [0, :func:`stable_dt`] and a concrete non-finite pressure are refused
    (:class:`~jaxskip.ParameterError`); traced values are the caller's to keep in range (the coupled
    rollout does). Jit-, vmap- and grad-able.

    ``clamp_blocks = ((bx, by), ...)`` (columns, static, smallest first): the
    clamp bites only where a column can run short (under and behind a stone).
    When all such columns fit in a block of ``bx`` × ``by`` columns placed around
    them at least one column from the grid's edge, the clamp's passes run on the
    first such block alone and touch only its pipes and those of its one-column
    ring (outside it every factor is 1 to round-off, as when the clamp is
    skipped); when they fit in none, on the whole grid. The same answer, a
    fraction of the cost on a large grid (a block within a column of the grid's
    side is skipped: the whole grid does its work). ``()``: always the whole grid.

    >>> import jax.numpy as jnp
    >>> grid = WaterGrid(shape=(16, 16), spacing=0.01, depth=0.05)
    >>> step = make_water_step(grid)
    >>> s1 = step(still_water(grid), jnp.zeros((16, 16)).at[8, 8].set(100.0))
    >>> bool(s1.height[8, 8] < grid.depth)    # pushed down under the pressure
    True
    """
    _check_grid(grid)
    l = grid.spacing
    H = grid.depth
    g = grid.gravity
    area = l * l
    c_axis = 2.0 / 3.0 * l * H
    c_diag = math.sqrt(2.0) / 6.0 * l * H
    k_axis = c_axis / l                       # c / L, times g * (head difference) gives dQ/dt
    k_diag = c_diag / (math.sqrt(2.0) * l)
    nx, ny = grid.shape
    if not isinstance(clamp_blocks, tuple):
        raise ParameterError(f"clamp_blocks must be a tuple of (bx, by) pairs, got {clamp_blocks!r}")
    for block in clamp_blocks:
        if (not isinstance(block, tuple) or len(block) != 2
                or not all(isinstance(v, numbers.Integral) and not isinstance(v, (bool, np.bool_)) for v in block)
                or not (1 <= block[0] <= nx and 1 <= block[1] <= ny)):
            raise ParameterError(f"clamp_blocks: each block must be a tuple of 2 ints (bx, by) with "
                                 f"1 <= bx <= {nx} and 1 <= by <= {ny} (the grid's shape), got {block!r}")
    clamp_blocks = tuple((int(bx), int(by)) for bx, by in clamp_blocks)   # (NumPy integers as Python ints)
    # A block keeps a column from either edge (its ring): one that cannot is the whole grid's work.
    blocks = tuple(b for b in clamp_blocks if b[0] <= nx - 2 and b[1] <= ny - 2)

    def _place(any_rows, size, n):
        """First index of a ``size`` block around the True entries of ``any_rows``, one entry from
        either end (:func:`_clamp`'s ring), and whether they fit in it."""
        lo = jnp.argmax(any_rows)
        hi = n - 1 - jnp.argmax(any_rows[::-1])
        start = jnp.clip(lo - (size - (hi - lo + 1)) // 2, 1, n - 1 - size)
        return start, (hi - lo < size) & (lo >= 1) & (hi <= n - 2)

    bound = stable_dt(l, H, g)

    def step(state: WaterState, pressure, dt=None) -> WaterState:
        if not isinstance(state, WaterState):   # (None met a raw AttributeError)
            raise ParameterError(f"state must be a jaxskip.WaterState (see still_water), got {type(state).__name__}")
        # (shapes are static: checked when traced; a (ny,) pressure broadcast over the rows in silence)
        if jnp.shape(pressure) != grid.shape:
            raise ParameterError(f"pressure must have the grid's shape {grid.shape}, got {jnp.shape(pressure)}")
        # every array where it lives, in one float type, and concrete heights, flows and clock finite (heights >= 0),
        # as run_water checks (a (1, ny) flow broadcast over every pipe, a NaN flow or clock ran on in silence)
        _check_state(grid, state)
        if jnp.iscomplexobj(pressure):
            raise ParameterError("pressure must be real [Pa per column], got a complex array")
        if not isinstance(pressure, jax.core.Tracer) and not bool(np.all(np.isfinite(np.asarray(pressure)))):
            raise ParameterError("pressure must be finite in every column [Pa]")   # (NaN heights followed in silence)
        # the state's float type throughout (a float64 pressure on a float32 state under x64 made float64
        # heights: a scan over the step met a raw carry-type error)
        pressure = jnp.asarray(pressure, dtype=state.height.dtype)
        if dt is None:
            dt = grid.time_step
        elif not isinstance(dt, jax.core.Tracer):   # a traced dt is the caller's to keep in range
            value = np.asarray(dt)
            if value.shape != () or value.dtype.kind not in "iuf" or not (0.0 <= float(value) <= bound * (1 + 1e-9)):
                raise ParameterError(f"dt must be a number in [0, {bound:.6g}] s (the pipe scheme's stability bound "
                                     f"for spacing {l} m and depth {H} m; split a longer step with "
                                     f"water_substeps()), got {dt!r}")
        dt = jnp.asarray(dt, dtype=state.height.dtype)   # (the state's type: the sponge's factors follow it)
        keep = 1.0 / (1.0 + dt * grid.damping)    # implicit linear damping: unconditionally stable
        if grid.boundary == "sponge":
            # the sponge's implicit relaxation of the pipe flows, in the same update (module docstring)
            keep_col, keep_pipes = _sponge_keep(grid, dt)
            keeps = tuple(keep * k for k in keep_pipes)
        else:
            keeps = (keep,) * 4
        h = state.height
        head = h + pressure / (grid.rho * g)   # pressure as metres of water
        qx = keeps[0] * (state.qx + dt * g * k_axis * (head[:-1, :] - head[1:, :]))
        qy = keeps[1] * (state.qy + dt * g * k_axis * (head[:, :-1] - head[:, 1:]))
        qd = keeps[2] * (state.qd + dt * g * k_diag * (head[:-1, :-1] - head[1:, 1:]))
        qa = keeps[3] * (state.qa + dt * g * k_diag * (head[:-1, 1:] - head[1:, :-1]))
        flows = (qx, qy, qd, qa)
        volume = h * area
        if grid.clamp != "zero":
            # Skip the clamp's passes when no column can run short (a real branch for one field;
            # under vmap all run): see _risk_margin.
            # (the flows are a conditional's operands, so XLA writes them once and the test reads them:
            # fused into it, each flow would be recomputed from the heads for each of its two columns)
            out = jax.lax.cond(dt > 0, lambda f: _outflow(_gather_out(*f)), lambda f: jnp.zeros_like(volume), flows)
            risk = _risk_margin(grid) * dt * out >= volume
            if not blocks:
                flows = jax.lax.cond(jnp.any(risk), lambda f: _clamp(grid, volume, f, dt), lambda f: f, flows)
            else:
                rows, cols = jnp.any(risk, axis=1), jnp.any(risk, axis=0)
                placed, fits = [], []
                for bx, by in blocks:
                    (i0, fit_x), (j0, fit_y) = _place(rows, bx, nx), _place(cols, by, ny)
                    placed.append((i0, j0, bx, by))
                    fits.append(fit_x & fit_y)
                # 0: no risk; then each block with its columns at risk listed, each block whole, the grid.
                branches = ([lambda f: f]
                            + [lambda f, b=b: _clamp(grid, volume, f, dt, b, listed=True) for b in placed]
                            + [lambda f, b=b: _clamp(grid, volume, f, dt, b) for b in placed]
                            + [lambda f: _clamp(grid, volume, f, dt)])
                short = jnp.sum(risk) <= CLAMP_LIST
                which = len(branches) - 1                  # none fits: the whole grid
                for b in reversed(range(len(blocks))):     # else the smallest block that fits...
                    which = jnp.where(fits[b], len(blocks) + 1 + b, which)
                for b in reversed(range(len(blocks))):     # ...with its columns at risk listed if few
                    which = jnp.where(fits[b] & short, 1 + b, which)
                which = jnp.where(jnp.any(risk), which, 0)
                flows = jax.lax.switch(which, branches, flows)
        height = h - (dt / area) * _net_out(*flows)
        if grid.clamp == "zero":
            height = jnp.maximum(height, 0.0)
        else:
            # A column the clamp emptied can land a rounding below zero (-1.4e-35 m in float32, after a 1e5 Pa
            # push was lifted; not traced to its cause, likely a subnormal volume in the clamp's test): set to 0,
            # a volume change of that rounding. (where, not maximum: at h = 0 exactly the gradient passes whole.)
            height = jnp.where(height < 0.0, jnp.zeros_like(height), height)
        if grid.boundary == "sponge":
            height = H + (height - H) * keep_col   # implicit relaxation towards rest
        return WaterState(height=height, qx=flows[0], qy=flows[1], qd=flows[2], qa=flows[3],
                          time=state.time + dt)

    return step


def placeless(grid: WaterGrid) -> WaterGrid:
    """``grid`` with its ``origin`` at (0, 0): the key of a compiled water (or coupled) program, whose step
    does not use where the grid is (the same grid object when it is there already)."""
    grid = _check_grid(grid)   # (None met an AttributeError; a review)
    return grid if grid.origin == (0.0, 0.0) else dataclasses.replace(grid, origin=(0.0, 0.0))


def _water_program(grid: WaterGrid, steps: int):
    """:func:`_water_runner`, keyed without ``grid.origin`` (:func:`placeless`)."""
    return _water_runner(placeless(grid), steps)


@functools.lru_cache(maxsize=32)
def _water_runner(grid: WaterGrid, steps: int):
    """A compiled scan of ``steps`` water steps, one per (grid, steps): no recompiles on new data."""
    step = make_water_step(grid)

    @jax.jit
    def go(s, p):
        return jax.lax.scan(lambda c, _: (step(c, p), None), s, None, length=steps)[0]

    return go


#: Water steps between two updates of :func:`run_water`'s progress line.
PROGRESS_CHUNK = 100


def run_water(grid: WaterGrid, state: WaterState, steps: int, pressure=None, progress: bool = False):
    """Advance ``steps`` (an integer in [0, 10^8]) water steps of ``grid.time_step`` under a constant
    ``pressure`` [Pa] per column, shape ``(nx, ny)`` (default none), in a jitted scan; returns the new
    :class:`WaterState` (its ``time`` advanced by ``steps * grid.time_step`` [s], step by step: in float32
    that sum drifts, +0.2 % after 2·10⁵ steps). ``state`` is checked first (its arrays' shapes; finite heights
    >= 0 when concrete). Each new ``steps`` compiles its own program (~0.4 s), kept for the next call; a new
    state or pressure does not compile. ``progress=True``: the steps run in scans of :data:`PROGRESS_CHUNK`
    (the same answer, to the bit) with a progress line on stderr, for large grids (a 4096² grid under a push
    takes seconds a step)."""
    _check_grid(grid)
    check_int("steps", steps, minimum=0, maximum=100_000_000)
    progress = check_bool("progress", progress)
    if not isinstance(state, WaterState):
        raise ParameterError(f"state must be a jaxskip.WaterState (see still_water), got {type(state).__name__}")
    _check_state(grid, state)
    if pressure is not None and jnp.iscomplexobj(pressure):   # (the cast dropped the imaginary part, with a warning)
        raise ParameterError("pressure must be real [Pa per column], got a complex array")
    dtype = state.height.dtype
    p = jnp.zeros(grid.shape, dtype) if pressure is None else jnp.asarray(pressure, dtype=dtype)
    if p.shape != grid.shape:
        raise ParameterError(f"pressure must have the grid's shape {grid.shape} (Pa per column), got {p.shape}")
    if not isinstance(p, jax.core.Tracer) and not bool(np.all(np.isfinite(np.asarray(p)))):
        raise ParameterError("pressure must be finite in every column [Pa]")
    # (asarray with the dtype makes it strongly typed: a weakly typed pressure would compile again; so would a
    # weakly typed clock, time=0.0 in a state built by hand, and it stayed weak in every state returned)
    state = dataclasses.replace(state, time=jnp.asarray(state.time, dtype=dtype))
    if not progress or steps <= PROGRESS_CHUNK:
        return _water_program(grid, steps)(state, p)
    from ._progress import ProgressLine

    line, done, t0 = ProgressLine(), 0, time.perf_counter()
    while done < steps:
        n = min(PROGRESS_CHUNK, steps - done)
        state = jax.block_until_ready(_water_program(grid, n)(state, p))
        done += n
        line.update(f"  water {grid.shape[0]}x{grid.shape[1]}: {done} of {steps} steps, "
                    f"{time.perf_counter() - t0:.1f} s")
    line.close()
    return state


def _check_state(grid: WaterGrid, state) -> None:
    """``state``: a :class:`WaterState` of ``grid`` (every array of its shape where it lives: heights at the
    column centres, flows on the pipes), and, when concrete, finite heights >= 0 m (a state made with
    ``dataclasses.replace`` or loaded from a file skips :func:`still_water`'s checks)."""
    if not isinstance(state, WaterState):
        raise ParameterError(f"state must be a jaxskip.WaterState (see still_water), got {type(state).__name__}")
    nx, ny = grid.shape
    for name, want in (("height", (nx, ny)), ("qx", (nx - 1, ny)), ("qy", (nx, ny - 1)), ("qd", (nx - 1, ny - 1)),
                       ("qa", (nx - 1, ny - 1)), ("time", ())):
        got = tuple(jnp.shape(getattr(state, name)))
        if got != want:
            raise ParameterError(f"state.{name} must have shape {want} for the grid's shape {grid.shape}, got {got}")
    _check_state_dtypes(state)
    if not isinstance(state.height, jax.core.Tracer):
        _check_heights("state.height", state.height)
    for name in ("qx", "qy", "qd", "qa", "time"):   # a NaN flow or clock ran on in silence
        value = getattr(state, name)
        if not isinstance(value, jax.core.Tracer) and not bool(np.all(np.isfinite(np.asarray(value)))):
            raise ParameterError(f"state.{name} must be finite ({'s' if name == 'time' else 'm³/s'}), got a "
                                 f"non-finite value")


_STATE_FIELDS = ("height", "qx", "qy", "qd", "qa", "time")


def _check_state_dtypes(state) -> None:
    """Every array of a :class:`WaterState` in one float type, float32 or float64 (static: checked while
    tracing too). A float16 flow or integer heights met a raw "scan body ... carry ... must have equal types"
    error, a float32 height among float64 flows a ``lax.cond`` one."""
    dtypes = {name: jnp.result_type(getattr(state, name)) for name in _STATE_FIELDS}
    if len(set(dtypes.values())) != 1 or dtypes["height"] not in (jnp.dtype(jnp.float32), jnp.dtype(jnp.float64)):
        shown = ", ".join(f"{n} {d.name}" for n, d in dtypes.items())
        raise ParameterError(f"state's arrays must all be float32 or all float64 (see still_water's dtype), got {shown}")


def _check_heights(name: str, height) -> None:
    """Concrete column heights [m]: finite and >= 0 in every column, else a ParameterError naming ``name``."""
    h = np.asarray(height, dtype=np.float64)
    ok = np.isfinite(h) & (h >= 0.0)
    if not np.all(ok):
        raise ParameterError(f"{name} must be finite and >= 0 m in every column, got {float(h[~ok].flat[0])!r}")


def total_volume(grid: WaterGrid, state: WaterState):
    """Total water volume [m³] (sum of column heights times the column area), a scalar, summed in the state's
    float type (in float32 its own rounding, ~1e-6 relative on a 64² grid, hides a smaller real change:
    sum ``np.asarray(state.height, np.float64)`` to check conservation there)."""
    _check_grid(grid)
    _check_state(grid, state)
    return jnp.sum(state.height) * grid.spacing ** 2


def _real_points(name: str, value, finite: bool = False):
    """``value`` as a JAX array of real numbers (a list or a traced value too); a string, a bool or an
    object array is refused with :class:`ParameterError` naming ``name`` (a list met ``x - origin`` as a
    raw TypeError). ``finite``: a concrete value with a NaN or an infinity is refused too (a traced one cannot
    be checked)."""
    if isinstance(value, (str, bytes)):
        raise ParameterError(f"{name} must be real numbers [m] (a number or an array), got {value!r}")
    try:
        arr = jnp.asarray(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be real numbers (a number or an array), got {value!r:.60}") from None
    if not (jnp.issubdtype(arr.dtype, jnp.floating) or jnp.issubdtype(arr.dtype, jnp.integer)):
        raise ParameterError(f"{name} must be real numbers (a number or an array), got dtype {arr.dtype}")
    # (NumPy's test: inside a trace a jnp operation on a concrete array is staged, and its result a tracer)
    if finite and not isinstance(arr, jax.core.Tracer) and not np.all(np.isfinite(np.asarray(arr))):
        raise ParameterError(f"{name} must be finite (no NaN or infinity), got {np.asarray(arr)!r:.80}")
    return arr


def _origin_xy(grid, origin):
    """``(ox, oy)`` [m]: ``grid.origin``, or ``origin`` checked to be two real numbers (may be traced)."""
    if origin is None:
        return grid.origin
    o = _real_points("origin", origin)
    if o.shape != (2,):
        raise ParameterError(f"origin must be the (x, y) [m] of column (0, 0): 2 numbers, got shape {o.shape}")
    return o[0], o[1]


def height_at(grid: WaterGrid, height, x, y, origin=None):
    """Water surface elevation [m] above the rest level at points ``(x, y)`` [m], bilinear.

    ``height``: column heights ``(nx, ny)``. ``origin``: centre ``(x, y)`` [m] of
    column ``(0, 0)`` (may be traced, for a window that moves; default
    ``grid.origin``). A point outside the grid is first clamped to the nearest point of the
    rectangle spanned by the column centres (each coordinate clipped separately) and interpolated
    there: beyond a side it reads the bilinear value along that edge (between the two nearest
    edge columns), beyond a corner the corner column's.
    ``x``, ``y``: real numbers or arrays of one shape [m]. Returns ``height - depth`` interpolated, with
    the shape of ``x`` [m]. Bad input raises :class:`ParameterError` naming it.
    """
    nx, ny = _check_grid(grid).shape
    # (finite when concrete: a NaN height or point read NaN in silence, where the docstring promised an error)
    height = _real_points("height", height, finite=True)
    if tuple(jnp.shape(height)) != grid.shape:
        raise ParameterError(f"height must have the grid's shape {grid.shape}, got {tuple(jnp.shape(height))}")
    x, y = _real_points("x", x, finite=True), _real_points("y", y, finite=True)
    if x.shape != y.shape:
        raise ParameterError(f"x and y must have one shape, got x {x.shape}, y {y.shape}")
    ox, oy = _origin_xy(grid, origin)
    fx = jnp.clip((x - ox) / grid.spacing, 0.0, nx - 1.0)
    fy = jnp.clip((y - oy) / grid.spacing, 0.0, ny - 1.0)
    i0 = jnp.clip(jnp.floor(fx).astype(jnp.int32), 0, nx - 2)
    j0 = jnp.clip(jnp.floor(fy).astype(jnp.int32), 0, ny - 2)
    tx, ty = fx - i0, fy - j0
    h00, h10 = height[i0, j0], height[i0 + 1, j0]
    h01, h11 = height[i0, j0 + 1], height[i0 + 1, j0 + 1]
    h = (1 - tx) * (1 - ty) * h00 + tx * (1 - ty) * h10 + (1 - tx) * ty * h01 + tx * ty * h11
    return h - grid.depth


def deposit(grid: WaterGrid, x, y, value, origin=None, into=None):
    """Spread point values (e.g. forces [N]) onto the columns, bilinearly: ``(nx, ny)``.

    The transpose of :func:`height_at`'s interpolation: the weights of each point
    sum to one, so the total is kept for points inside the grid; points outside
    are dropped. ``x, y, value``: arrays of one shape; ``origin`` as in :func:`height_at`.
    ``into``: an ``(nx, ny)`` array to add to (default zeros); adding in place inside
    a loop costs the points, not the grid: a loop over the points adds each one's
    2 x 2 corner weights where they land (a slice update, in place). No scatter, so
    XLA:CPU can compile a loop that deposits into one function (a scatter keeps the
    whole loop out of it: ``jaxskip/_xla.py``).
    """
    nx, ny = _check_grid(grid).shape
    # (a NaN value wrote NaN into its 2 x 2 columns; a NaN point is dropped, below)
    x, y, value = _real_points("x", x), _real_points("y", y), _real_points("value", value, finite=True)
    shapes = {name: tuple(jnp.shape(v)) for name, v in (("x", x), ("y", y), ("value", value))}
    if len(set(shapes.values())) != 1:
        raise ParameterError("x, y and value must have one shape, got " + ", ".join(f"{k} {v}" for k, v in shapes.items()))
    if into is not None and tuple(jnp.shape(into)) != grid.shape:  # (a wrong shape wrote to clamped columns)
        raise ParameterError(f"into must have the grid's shape {grid.shape}, got {tuple(jnp.shape(into))}")
    if into is not None and not jnp.issubdtype(jnp.result_type(into), jnp.floating):   # (an int array truncated
        raise ParameterError(f"into must be a floating array, got dtype {jnp.result_type(into)}")  # the weights to 0)
    ox, oy = _origin_xy(grid, origin)
    fx = jnp.ravel((x - ox) / grid.spacing)
    fy = jnp.ravel((y - oy) / grid.spacing)
    inside = (fx >= 0) & (fx <= nx - 1) & (fy >= 0) & (fy <= ny - 1)    # (False for a NaN point)
    # a point outside (or NaN) is dropped with its weights: a NaN point's NaN fractions times its zeroed value
    # were NaN, added into the 2 x 2 columns it was clipped to
    fx = jnp.where(inside, jnp.clip(fx, 0.0, nx - 1.0), 0.0)
    fy = jnp.where(inside, jnp.clip(fy, 0.0, ny - 1.0), 0.0)
    i0 = jnp.clip(jnp.floor(fx).astype(jnp.int32), 0, nx - 2)
    j0 = jnp.clip(jnp.floor(fy).astype(jnp.int32), 0, ny - 2)
    tx, ty = fx - i0, fy - j0
    v = jnp.where(inside, jnp.ravel(value), 0.0)
    # (P, 2, 2): point p's weight on columns (i0 + a, j0 + b)
    w = jnp.stack([jnp.stack([(1 - tx) * (1 - ty) * v, (1 - tx) * ty * v], -1),
                   jnp.stack([tx * (1 - ty) * v, tx * ty * v], -1)], 1)
    out = jnp.zeros(grid.shape, jnp.result_type(value, float)) if into is None else into
    w = w.astype(out.dtype)   # (into's type: float64 values into a float32 array met a raw dtype error)

    def add(p, a):
        corner = (i0[p], j0[p])
        return jax.lax.dynamic_update_slice(a, jax.lax.dynamic_slice(a, corner, (2, 2)) + w[p], corner)

    return jax.lax.fori_loop(0, fx.shape[0], add, out)


__all__ = ["BOUNDARIES", "CLAMPS", "MAX_COLUMNS", "WaterGrid", "WaterState", "deposit", "height_at", "make_water_step",
           "placeless", "run_water", "stable_dt", "still_water", "total_volume", "water_substeps"]
