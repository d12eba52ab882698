"""fairfit: fair NURBS curves and surfaces from measured points.

numpy points in, fair NURBS out::

    import numpy as np, fairfit
    t = np.linspace(0, np.pi, 200)
    curve = fairfit.fit_curve(np.c_[np.cos(t), 0.5 * np.sin(t)], rel_tol=1e-3)
    curve(np.linspace(0, 1, 5))          # (5, 2) points
    curve.report["max_deviation"]        # the fit's report, the keys of `fairfit curve --report`
    curve.save("curve.step")             # .json .step .iges .obj .stl .ply .svg .png .html

The keyword names and defaults of :func:`fit_curve`, :func:`fit_chain` and :func:`fit_surface` are
those of the command-line tool's ``fairfit curve`` (``--chain``) and ``fairfit surface`` options
(``--rel-tol`` is ``rel_tol``), and the same points and seed give a curve whose JSON is byte-identical
to the CLI's ``-o`` file. Errors
raise :class:`FairfitError` (a ``ValueError``) with the CLI's one-line message. Every fit and every
batch evaluation runs with the GIL released; ``threads`` sets the size of the fit's own thread pool
(results do not depend on it). :mod:`fairfit.ray` fans fits out on a Ray cluster.
"""

from __future__ import annotations

import warnings as _warnings
from os import PathLike, fspath
from typing import List, Optional, Sequence, Tuple, Union

import numpy as _np

from ._fairfit import Curve, FairfitError, Surface, __version__
from ._fairfit import fit_chain as _fit_chain
from ._fairfit import fit_curve as _fit_curve
from ._fairfit import fit_surface as _fit_surface
from ._fairfit import fit_surface_from_mesh as _fit_surface_from_mesh
from ._fairfit import read as _read
from ._fairfit import read_points as _read_points

__all__ = [
    "Curve",
    "FairfitError",
    "FairfitWarning",
    "Surface",
    "DEFAULT_CORNER_ANGLE",
    "DEFAULT_MAX_POINTS",
    "DEFAULT_MAX_SECTIONS",
    "fit_chain",
    "fit_curve",
    "fit_surface",
    "fit_surface_from_mesh",
    "read",
    "read_points",
    "__version__",
]

#: The turning angle in degrees above which a point is a corner (``fairfit curve --corner-angle``).
DEFAULT_CORNER_ANGLE = 60.0

#: The most points an input may hold by default (``fairfit --max-points``).
DEFAULT_MAX_POINTS = 10_000_000

#: The most sections a surface may have by default (``fairfit surface --max-sections``).
DEFAULT_MAX_SECTIONS = 1000


class FairfitWarning(UserWarning):
    """A warning of a fit (the CLI's ``warning:`` lines): a tolerance not met, dropped duplicates."""


def _points(points, what: str = "points") -> _np.ndarray:
    """`points` as a C-contiguous float64 (n, 2) or (n, 3) array, or FairfitError."""
    try:
        a = _np.asarray(points)
    except ValueError as e:  # numpy >= 1.24 refuses ragged nested sequences
        raise FairfitError(
            f"invalid input data: {what} must be an (n, 2) or (n, 3) array of numbers, "
            f"and its rows differ in length ({e})"
        ) from None
    if a.dtype == object:
        raise FairfitError(
            f"invalid input data: {what} must be an (n, 2) or (n, 3) array of numbers; "
            "its rows differ in length or hold other objects"
        )
    if a.dtype.kind not in "fiu":
        raise FairfitError(
            f"invalid input data: {what} must be numbers, got an array of dtype {a.dtype}"
        )
    if a.ndim != 2 or a.shape[1] not in (2, 3):
        raise FairfitError(
            f"invalid input data: {what} must be an (n, 2) or (n, 3) array, got shape {a.shape}"
        )
    return _np.ascontiguousarray(a, dtype=_np.float64)


def _vector(v, what: str) -> Optional[list]:
    if v is None:
        return None
    a = _np.asarray(v, dtype=_np.float64).ravel()
    if a.size not in (2, 3):
        raise FairfitError(f"{what} must be X,Y or X,Y,Z, got {a.size} values")
    return [float(a[0]), float(a[1]), float(a[2]) if a.size == 3 else 0.0]


def _direction(v, what: str) -> Optional[list]:
    if v is None:
        return None
    a = _np.asarray(v, dtype=_np.float64).ravel()
    if a.size != 3:
        raise FairfitError(f"{what} must be X,Y,Z, got {a.size} values")
    return [float(a[0]), float(a[1]), float(a[2])]


def _warn(messages) -> None:
    for m in messages:
        _warnings.warn(m, FairfitWarning, stacklevel=3)


def fit_curve(
    points,
    *,
    tol: Optional[float] = None,
    rel_tol: float = 1e-3,
    method: str = "integrated",
    degree: Union[str, int] = "auto",
    control_points: Optional[int] = None,
    closed: Optional[bool] = None,
    corner_angle: Optional[float] = DEFAULT_CORNER_ANGLE,
    ends: str = "pinned",
    seed: int = 0,
    threads: Optional[int] = None,
    band_fairing: bool = True,
    span_fairness: Optional[float] = None,
    param: str = "centripetal",
    knots: str = "refine",
    correction_rounds: int = 0,
    smoothing: float = 0.0,
    smoothing_order: int = 2,
    start_tangent=None,
    end_tangent=None,
    name: Optional[str] = None,
    pareto: bool = False,
    outliers: str = "auto",
    start: Optional[str] = None,
    end: Optional[str] = None,
    max_points: int = DEFAULT_MAX_POINTS,
    weights=None,
    interpolate=None,
) -> Union[Curve, Tuple[Curve, List[Curve]]]:
    """Fits a fair curve to ordered points within a tolerance: ``fairfit curve`` from Python.

    Every keyword is the CLI option of the same name (``rel_tol`` is ``--rel-tol``), with the same
    default, and the same points and ``seed`` give a curve whose :meth:`Curve.to_json` is
    byte-identical to what ``fairfit curve POINTS -o curve.json`` writes, and a ``report`` with the
    keys of ``--report``, in every method. A keyword the chosen method ignores (``knots`` with the
    integrated method, ``span_fairness`` with ``lsq``, ...) raises :class:`FairfitError`, as the CLI
    refuses the option.

    points: an (n, 2) or (n, 3) array of floats, or anything ``np.asarray`` makes one of. Consecutive
        duplicate points are dropped (a :class:`FairfitWarning` says how many), as the CLI does.
    tol: absolute tolerance on the maximum orthogonal deviation (``--tol``); takes precedence over
        ``rel_tol``.
    rel_tol: tolerance relative to the largest side of the points' bounding box (``--rel-tol``,
        default 1e-3).
    method: ``"integrated"`` (knots by particle swarm optimisation, fitting and fairing in one, the
        default), ``"lsq"`` (least squares with a tolerance-driven knot count) or ``"fit-then-fair"``.
    degree: ``"auto"`` (integrated only, its default: degrees 3 to 5, the fairest kept) or 1 to 15;
        ``lsq`` and ``fit-then-fair`` default to 3.
    control_points: a fixed number of control points instead of the fewest within the tolerance
        (integrated only).
    closed: None detects closed data (the last point repeats the first, or the ends are a gap of at
        most the tolerance apart that the data continue smoothly through: the report's
        ``closed_by_gap``), True treats the points as a closed curve (``--closed``), False as
        an open one.
    corner_angle: turning angle in degrees above which a point is a corner kept as a C0 knot
        (``--corner-angle``, default 60); None detects no corners (``--no-corners``).
    ends: ``"pinned"`` (the curve starts and ends at the first and last points) or ``"free"`` (a last
        fairing pass moves them within the tolerance; integrated, open curves).
    seed: random seed of the swarm search.
    threads: worker threads of this fit (``--threads``; None: one per core). Results do not depend on
        it.
    band_fairing: False skips the final band fairing (``--no-band-fairing``).
    span_fairness: per-span fairness target F* (``--span-fairness``; integrated).
    param: ``"centripetal"``, ``"chord"`` or ``"uniform"`` (``--param``).
    knots: ``"refine"``, ``"averaging"`` or ``"adaptive"`` (``--knots``; lsq and fit-then-fair).
    correction_rounds: parameter-correction rounds per least-squares fit.
    smoothing: scale-free smoothing weight λ (``--smoothing``), with ``smoothing_order`` 2 or 3.
    outliers: ``"auto"`` (the default: isolated spikes excluded and listed in the report's
        ``outliers``) or ``"off"`` (every point kept; a fit that misses the tolerance because of
        spikes names them, in its error or a :class:`FairfitWarning`). Either way the noise σ is
        measured and a tolerance below the noise is raised to the meaningful tolerance, with a
        warning (``--outliers``; docs/fit.md "Screening").
    start, end: a condition at the first or last point of an open curve, the text of ``--start`` /
        ``--end``: ``"point:X,Y[,Z]"`` (G0), ``"tangent:X,Y[,Z]"`` (G1, direction only) or
        ``"curvature:X,Y[,Z]:KAPPA"`` (G2, signed curvature; in 3-D also
        ``"curvature:X,Y,Z:KX,KY,KZ"``). Every method holds them; the report's ``end_conditions``
        says the continuity achieved and what it cost in F (docs/constraints.md).
    start_tangent, end_tangent: a tangent direction (X, Y[, Z]) at the ends, the same as
        ``start="tangent:X,Y"`` (``--start-tangent``); not with ``start`` / ``end``.
    max_points: most points the input may hold (``--max-points``, default 10^7); more raise
        :class:`FairfitError`.
    weights: one weight per row of ``points`` (``--weights``, or a ``w`` column): row i is held to
        ``tol / w_i``, and weight 0 ignores it. Weights must be finite, >= 0 and not all 0. Every
        method honours them; the report's ``point_constraint_fit`` says how (docs/constraints.md).
    interpolate: rows of ``points`` the curve passes through, within 1e-9 of the data's size
        (``--interpolate I,J,...``); the report's ``point_constraints`` lists each with its
        distance. A run of consecutive duplicate rows counts as one point: it takes the largest
        weight of the run and is interpolated when any of its rows is.
    name: what the report's ``input`` and the messages call the points (default ``"<array>"``).
    pareto: also return the Pareto front of (max deviation, F) at the fitted count (``--pareto``;
        integrated only): a list of :class:`Curve` by increasing deviation (so decreasing F), each
        with a ``report`` of the CSV's columns (``control_points``, ``max_deviation``,
        ``rms_deviation``, ``fairness``, ``max_span_fairness``); ``curve.report["pareto_members"]``
        is its length.

    Returns the :class:`Curve`, with ``curve.report`` the dict ``fairfit curve --report`` writes;
    with ``pareto=True``, the pair ``(curve, front)``.
    Raises :class:`FairfitError` for invalid points or options, with the CLI's message.
    """
    if isinstance(degree, bool) or not isinstance(degree, (str, int, _np.integer)):
        raise FairfitError(f"degree: expected `auto` or a degree from 1 to 15, got `{degree!r}`")
    for what, cond in (("start", start), ("end", end)):
        if cond is not None and not isinstance(cond, str):
            raise FairfitError(
                f"{what}: expected text such as 'tangent:1,0' (the CLI's --{what}), got {cond!r}"
            )
    if isinstance(max_points, bool) or not isinstance(max_points, (int, _np.integer)) or max_points < 0:
        raise FairfitError(f"max_points must be a whole number >= 0, got {max_points!r}")
    if weights is not None:
        w = _np.asarray(weights, dtype=float)
        if w.ndim != 1:
            raise FairfitError(f"weights: expected one number per point, got an array of shape {w.shape}")
        weights = [float(x) for x in w]
    if interpolate is not None:
        idx = _np.asarray(interpolate)
        if idx.ndim != 1 or (idx.size and (idx.dtype.kind not in "iu" or idx.min() < 0)):
            raise FairfitError(f"interpolate: expected row indices >= 0, got {interpolate!r}")
        interpolate = [int(i) for i in idx]
    curve, warnings, front = _fit_curve(
        _points(points),
        None if tol is None else float(tol),
        float(rel_tol),
        method,
        str(degree),
        control_points,
        closed,
        None if corner_angle is None else float(corner_angle),
        ends,
        int(seed),
        threads,
        bool(band_fairing),
        span_fairness,
        param,
        knots,
        int(correction_rounds),
        float(smoothing),
        int(smoothing_order),
        _vector(start_tangent, "start_tangent"),
        _vector(end_tangent, "end_tangent"),
        name,
        bool(pareto),
        outliers,
        start,
        end,
        int(max_points),
        weights,
        interpolate,
    )
    _warn(warnings)
    return (curve, front) if pareto else curve


def fit_chain(
    pieces: Sequence,
    continuity: str = "g2",
    *,
    tol: Optional[float] = None,
    rel_tol: float = 1e-3,
    degree: Union[str, int] = "auto",
    corner_angle: Optional[float] = DEFAULT_CORNER_ANGLE,
    seed: int = 0,
    threads: Optional[int] = None,
    band_fairing: bool = True,
    span_fairness: Optional[float] = None,
    outliers: str = "auto",
    start: Optional[str] = None,
    end: Optional[str] = None,
    start_tangent=None,
    end_tangent=None,
    names: Optional[Sequence[str]] = None,
    max_points: int = DEFAULT_MAX_POINTS,
) -> Tuple[Curve, List[Curve]]:
    """Fits several point sets as one fair chain of curves joining with G1 or G2 continuity:
    ``fairfit curve A.csv B.csv ... --chain g1|g2`` from Python.

    The joins are where the fairest single curve through every point passes (its position, tangent
    and, for G2, curvature vector there); each piece is the integrated method's fit of its points
    under those join conditions, or the single curve's part between the joins when that is fairer
    (docs/constraints.md, "Chains"). The same points and ``seed`` give curves whose
    :meth:`Curve.to_json` is byte-identical to the CLI's ``-o FILE`` (the joined chain) and
    ``FILE_k`` (piece k) files, and a report with the keys of its ``--report``.

    pieces: a list of (n_k, 2) or (n_k, 3) arrays of floats, the point sets in order, each ordered
        along the chain: the last point of piece k and the first of piece k + 1 must lie within twice
        the tolerance of each other (they may be the same point). Consecutive duplicate points are
        dropped (a :class:`FairfitWarning` says how many), as the CLI does.
    continuity: ``"g1"`` (position and tangent direction) or ``"g2"`` (also the curvature vector,
        the default) at every join (``--chain``).
    tol, rel_tol: absolute tolerance, or relative to the largest side of the bounding box of all
        pieces together (``--tol``, ``--rel-tol``, default 1e-3); every piece is held to it.
    degree, corner_angle, seed, threads, band_fairing, span_fairness, outliers, max_points: as in
        :func:`fit_curve` (the integrated method's keywords; ``outliers`` screens the union of the
        pieces). The keywords of one curve's shape or of one point set (``method``,
        ``control_points``, ``closed``, ``ends``, ``weights``, ``interpolate``, ``pareto``) do not
        apply to a chain, as the CLI refuses those options with ``--chain``.
    start, end, start_tangent, end_tangent: the chain's own conditions at the first point of the
        first piece and the last point of the last piece, as in :func:`fit_curve`.
    names: what each piece's report and the messages call its points (default ``"<piece k>"``,
        1-based).

    Returns ``(chain, pieces)``: ``chain`` the joined chain, one :class:`Curve` on ``[0, N]`` for N
    pieces (piece k, 1-based, on ``[k - 1, k]``; every join a knot of full multiplicity, so exactly
    as continuous as the pieces), and ``pieces`` the N piece curves in input order. ``chain.report``
    is the dict ``--report`` writes: ``chain`` (the continuity), ``pieces`` (each piece's own
    report, also ``pieces[k].report``, with ``from_single_curve``), ``joins`` (for each join:
    ``pieces``, ``point``, ``data_gap``, ``position_gap``, ``tangent_angle`` in radians,
    ``curvature_relative`` = ``|k1 - k2| / max(|k1|, |k2|)`` of the two curvature vectors,
    ``curvature``), ``tolerance``, ``tolerance_met``, ``max_deviation``, ``length``, ``fairness``,
    ``single_curve_fairness`` and ``fairness_ratio``.

    Raises :class:`FairfitError` with the CLI's one-line message for fewer than two pieces, pieces
    that do not meet, a continuity other than ``"g1"`` / ``"g2"``, non-finite points and invalid
    options; a piece that misses the tolerance is a :class:`FairfitWarning`.
    """
    if isinstance(pieces, (str, bytes)) or not hasattr(pieces, "__len__"):
        raise FairfitError(
            f"pieces must be a list of (n, 2) or (n, 3) arrays (the point sets, in order), got {type(pieces).__name__}"
        )
    if not isinstance(continuity, str):
        raise FairfitError(f"continuity: expected `g1` or `g2`, got `{continuity!r}`")
    if isinstance(degree, bool) or not isinstance(degree, (str, int, _np.integer)):
        raise FairfitError(f"degree: expected `auto` or a degree from 1 to 15, got `{degree!r}`")
    for what, cond in (("start", start), ("end", end)):
        if cond is not None and not isinstance(cond, str):
            raise FairfitError(
                f"{what}: expected text such as 'tangent:1,0' (the CLI's --{what}), got {cond!r}"
            )
    arrays = [_points(p, f"piece {k + 1}") for k, p in enumerate(pieces)]
    joined, curves, warnings = _fit_chain(
        arrays,
        continuity,
        None if tol is None else float(tol),
        float(rel_tol),
        str(degree),
        None if corner_angle is None else float(corner_angle),
        int(seed),
        threads,
        bool(band_fairing),
        span_fairness,
        outliers,
        start,
        end,
        _vector(start_tangent, "start_tangent"),
        _vector(end_tangent, "end_tangent"),
        None if names is None else [str(n) for n in names],
        _count(max_points, "max_points"),
    )
    _warn(warnings)
    return joined, curves


def fit_surface(
    sections: Sequence,
    *,
    tol: Optional[float] = None,
    rel_tol: float = 1e-3,
    degree: int = 3,
    degree_v: int = 3,
    max_ctrl: int = 120,
    v_params: str = "chord",
    approximate_v: Optional[int] = None,
    smooth_v: float = 1e-3,
    clamped_seam: bool = False,
    threads: Optional[int] = None,
    names: Optional[Sequence[str]] = None,
    max_sections: int = DEFAULT_MAX_SECTIONS,
    start_tangent_v=None,
    end_tangent_v=None,
    corner_angle: Optional[float] = DEFAULT_CORNER_ANGLE,
    split_at_le: bool = False,
    open_sections: bool = False,
) -> Surface:
    """A fair surface through ordered sections: ``fairfit surface SECTIONS...`` from Python.

    sections: a list of (n_k, 2) or (n_k, 3) arrays, one per section, in stacking order (a closed
        section repeats its first point at the end).
    tol / rel_tol: absolute tolerance, or relative to the largest section's extent (``--tol``,
        ``--rel-tol``, default 1e-3).
    degree, degree_v: degrees across the sections' points (u) and across the sections (v).
    max_ctrl: most control points per section (``--max-ctrl``).
    v_params: ``"chord"`` or ``"centripetal"`` parameters of the sections along v.
    approximate_v: approximate across the sections with this many control points (``--approximate-v``).
    smooth_v: smoothing across the sections (``--smooth-v``).
    clamped_seam: closed sections clamped at a seam instead of periodic (``--clamped-seam``).
    threads: worker threads (None: one per core); names: what the report calls each section.
    max_sections: most sections (``--max-sections``, default 1,000: the loft's work grows with the
        count); more raise :class:`FairfitError` before any work.
    start_tangent_v / end_tangent_v: a direction (X, Y, Z) for the derivative across the sections
        along the whole first / last section (``--start-tangent-v``, ``--end-tangent-v``; only the
        direction counts, the report's ``v_end_tangents`` gives the largest angle reached).
    corner_angle: turning angle in degrees above which a section point is a corner
        (``--corner-angle``, default 60): a seam corner keeps the seam C0, and inner corners, when
        every section has the same number, are held as C0 knot lines (the report's ``corners``);
        None smooths inner corners over (``--no-corners``).
    split_at_le: airfoil sections: every section's leading edge (the point farthest from the midpoint
        of its first and last points) pinned to u = 0.5, each section curve through it there, so the
        iso-curve u = 0.5 is the leading edge (``--split-at-le``; the report's ``split_at_le``).
    open_sections: keep open sections open (``--open-sections``). By default a section whose last
        point lies within the tolerance (and a few of its spacings) of its first, continuing smoothly
        through that gap, is fitted closed (the report's per-section ``closed_by_gap``).

    One knot vector is searched for all sections together (the sections' fits are not independent),
    then the compatible curves are skinned. Returns the :class:`Surface` with the report
    ``fairfit surface --report`` writes.
    """
    arrays = [_points(s, f"section {k}") for k, s in enumerate(sections)]
    return _fit_surface(
        arrays,
        None if tol is None else float(tol),
        float(rel_tol),
        int(degree),
        int(degree_v),
        int(max_ctrl),
        v_params,
        approximate_v,
        float(smooth_v),
        bool(clamped_seam),
        threads,
        None if names is None else [str(n) for n in names],
        _count(max_sections, "max_sections"),
        _direction(start_tangent_v, "start_tangent_v"),
        _direction(end_tangent_v, "end_tangent_v"),
        None if corner_angle is None else float(corner_angle),
        bool(split_at_le),
        bool(open_sections),
    )


def fit_surface_from_mesh(
    path: Union[str, PathLike],
    slices: int,
    *,
    axis: str = "z",
    normal=None,
    gap_factor: float = 5.0,
    tol: Optional[float] = None,
    rel_tol: float = 1e-3,
    degree: int = 3,
    degree_v: int = 3,
    max_ctrl: int = 120,
    v_params: str = "chord",
    approximate_v: Optional[int] = None,
    smooth_v: float = 1e-3,
    clamped_seam: bool = False,
    threads: Optional[int] = None,
    max_sections: int = DEFAULT_MAX_SECTIONS,
    start_tangent_v=None,
    end_tangent_v=None,
    corner_angle: Optional[float] = DEFAULT_CORNER_ANGLE,
    split_at_le: bool = False,
    open_sections: bool = False,
) -> Surface:
    """A fair surface through a mesh or point cloud (.ply, .stl, .obj) cut by ``slices`` planes along
    ``axis`` (or ``normal``): ``fairfit surface MESH --slices N --axis z``. The other keywords are
    those of :func:`fit_surface`."""
    return _fit_surface_from_mesh(
        fspath(path),
        int(slices),
        axis,
        _vector(normal, "normal"),
        float(gap_factor),
        None if tol is None else float(tol),
        float(rel_tol),
        int(degree),
        int(degree_v),
        int(max_ctrl),
        v_params,
        approximate_v,
        float(smooth_v),
        bool(clamped_seam),
        threads,
        _count(max_sections, "max_sections"),
        _direction(start_tangent_v, "start_tangent_v"),
        _direction(end_tangent_v, "end_tangent_v"),
        None if corner_angle is None else float(corner_angle),
        bool(split_at_le),
        bool(open_sections),
    )


def _count(n, what: str) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, _np.integer)) or n < 0:
        raise FairfitError(f"{what} must be a whole number >= 0, got {n!r}")
    return int(n)


def read(path: Union[str, PathLike], index: int = 0) -> Union[Curve, Surface]:
    """Reads a curve or surface: fairfit JSON, STEP or IGES (for STEP and IGES the first B-spline
    surface if the file holds one, else its first curve, in millimetres; ``index`` picks another)."""
    return _read(fspath(path), int(index))


def read_points(path: Union[str, PathLike]) -> _np.ndarray:
    """The points of a point file as ``fairfit curve`` reads them (CSV, TSV or whitespace columns,
    Selig or Lednicer airfoil ``.dat`` files; consecutive duplicates dropped): an (n, 2) or (n, 3)
    array."""
    return _read_points(fspath(path))
