"""The pictures of searches and sweeps (plot_search, plot_sweep): built from small hand-made results
shaped as the searches and sweeps make them (no simulation, but one smallest real grid search), and
checked on the matplotlib figures themselves: what is drawn, its ticks, labels, legends and titles."""

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.container import ErrorbarContainer

from optimize import EXPLODING, VANISHING, SearchResult, gradient_health, grid_search, make_box, plot_search, plot_sweep
from optimize.search import _search_figure
from optimize.sweep import _sweep_figure

#: A throw whose numbers round differently to integers and to one decimal.
BEST = {"speed": 7.514, "tilt": 5.66, "attack": 25.61, "spin": 11.43}


def exhaustive(method: str, counts) -> SearchResult:
    """A grid or random search's result (as optimize.search._exhaustive makes it) over throws of ``counts``."""
    counts = np.asarray(counts)
    best = int(counts.max())
    history = [{"iteration": 0, "bounces": [best], "objective": None, "best": best, "nonfinite": 0,
                "count_histogram": np.bincount(counts).tolist()}]
    return SearchResult(method, BEST, best, history, make_box(), 1.0, int(counts.size), 0, best_distance=3.21)


def local(counts) -> SearchResult:
    """A local search's result: one polish entry listing every throw's count."""
    counts = list(counts)
    history = [{"iteration": 0, "phase": "polish", "bounces": counts, "distance": [1.0] * len(counts),
                "objective": None, "best": max(counts), "nonfinite": 0, "points": {}}]
    return SearchResult("local", BEST, max(counts), history, make_box(), 1.0, len(counts), 0, best_distance=3.21)


def gradient(norms, bounces, polish=None) -> SearchResult:
    """A gradient search's result: ``bounces`` (iterations + 1, starts) true counts, ``norms``
    (iterations, starts) raw gradient norms (None: non-finite), then a polish entry of ``polish`` counts."""
    history, best = [], 0
    for it, b in enumerate(bounces):
        best = max(best, max(b))
        h = {"iteration": it, "bounces": list(b), "objective": [0.0] * len(b), "best": best, "nonfinite": 0,
             "points": {}}
        if it < len(norms):
            h["grad_norm"] = list(norms[it])
        else:
            h["objective"] = None
        history.append(h)
    if polish is not None:
        best = max(best, max(polish))
        history.append({"iteration": len(bounces), "phase": "polish", "bounces": list(polish), "objective": None,
                        "best": best, "nonfinite": 0, "points": {}})
    return SearchResult("gradient", BEST, best, history, make_box(), 1.0, 0, len(norms) * len(norms[0]),
                        best_distance=3.21)


#: Three starts, three iterations: start 0 explodes once, start 1 dips below VANISHING once (the
#: reviewer's 3e-9), start 2 vanishes at every iteration.
NORMS = [[2e6, 1.8, 4e-12], [1e-3, 3e-9, 4e-12], [77.0, 3.4, 4e-12]]
BOUNCES = [[9, 4, 0], [1, 8, 0], [8, 10, 0], [1, 10, 0]]
POLISH = [10, 11, 1, 10, 12, 9]


def umin_result(umin, at_low, res=0.25, speed_range=(0.5, 8.0)):
    """A U_min sweep's result (as optimize.sweep.assemble makes it)."""
    tilts = [10.0 * (i + 1) for i in range(len(umin))]
    finite = [(u, t) for u, t in zip(umin, tilts) if u is not None]
    best = min(finite) if finite else (None, None)
    spec = {"kind": "umin", "tilts": tilts, "attacks": [20.0], "speed_range": list(speed_range), "iterations": 5,
            "spin": 65.0, "stone": "clanet", "attitude": "fixed"}
    return {"spec": spec, "umin": list(umin), "bounces_at_high": [0 if u is None else 1 for u in umin],
            "bounces_at_low": list(at_low), "best_tilt": best[1], "best_umin": best[0], "best_tilt_fit": None,
            "best_umin_fit": None, "resolution": res}


def domain_result():
    spec = {"kind": "domain", "tilts": [10.0, 20.0, 30.0], "attacks": [0.0, 15.0, 30.0, 45.0], "speed": 3.5,
            "spin": 65.0, "stone": "clanet", "attitude": "fixed"}
    b = [[0, 4, 3, 0], [0, 2, 1, 0], [0, 1, 0, 0]]
    return {"spec": spec, "bounces": b, "first_contact_time": [[None] * 4] * 3}


def legend_texts(ax) -> list:
    legend = ax.get_legend()
    return [] if legend is None else [t.get_text() for t in legend.get_texts()]


def tick_labels(ax) -> list:
    ax.figure.draw_without_rendering()
    return [t.get_text() for t in ax.get_xticklabels()]


# --- grid, random and local searches: the histogram of the counts -------------------------------------

@pytest.mark.parametrize("result", [exhaustive("grid", [0] * 8 + [1, 1, 1, 2, 5, 13, 14, 21]),
                                    exhaustive("random", [0, 3, 3, 3, 7, 7]), local([2, 2, 5, 0, 5, 5])],
                         ids=["grid", "random", "local"])
def test_exhaustive_search_draws_the_histogram_of_its_counts(result):
    """Not one dot at "iteration 0": a bar per true bounce count, of the throws that gave it, summing to
    the throws evaluated, the best count's bar marked, integer count ticks."""
    fig = _search_figure(result)
    (ax,) = fig.axes
    bars = {round(p.get_x() + p.get_width() / 2): p for p in ax.patches}
    heights = {k: p.get_height() for k, p in bars.items()}
    assert sum(heights.values()) == result.forward_throws
    counts = result.history[0].get("count_histogram") or np.bincount(result.history[0]["bounces"]).tolist()
    assert [heights.get(k, 0) for k in range(len(counts))] == counts
    best = bars[result.best_bounces]
    assert best.get_facecolor() != bars[0].get_facecolor()  # the best count marked
    assert any(f"best count found: {result.best_bounces} bounces" in t for t in legend_texts(ax))
    ticks = ax.get_xticks()
    assert np.all(ticks == np.round(ticks))
    assert ax.get_xlabel() == "true bounce count (exact simulation) [bounces]"
    assert ax.get_ylabel() == "number of throws"
    assert f"{result.forward_throws} throws" in ax.get_title()


def test_histogram_turns_logarithmic_when_the_counts_span_decades():
    fig = _search_figure(exhaustive("random", [0] * 500 + [1] * 40 + [6]))
    (ax,) = fig.axes
    assert ax.get_yscale() == "log" and ax.get_ylabel() == "number of throws (log scale)"
    assert sum(p.get_height() for p in ax.patches) == 541


def test_a_real_grid_search_plots_its_throws():
    """The smallest real grid search (one searched parameter, 2 throws): its histogram holds both throws."""
    box = make_box({"speed": (4.0, 8.0)}, {"tilt": 20.0, "attack": 10.0, "spin": 10.0})
    r = grid_search(box, per_axis=2)
    (ax,) = _search_figure(r).axes
    assert sum(p.get_height() for p in ax.patches) == 2 == r.forward_throws


# --- gradient searches ------------------------------------------------------------------------------

def test_gradient_plot_has_integer_iteration_ticks_and_a_polish_tick():
    """Iterations 0..3 as integer ticks on both panels (no 0.5 ticks), the polish at its own tick
    labelled "polish" after them (not as an "iteration 4"), and the same iteration axis on both panels."""
    fig = _search_figure(gradient(NORMS, BOUNCES, POLISH))
    left, right = fig.axes
    labels = tick_labels(left)
    assert labels == ["0", "1", "2", "3", "polish"]
    assert tick_labels(right) == labels
    assert list(left.get_xticks()) == [0, 1, 2, 3, 4]
    assert left.get_xlim() == right.get_xlim()
    polish = [line for line in left.lines if line.get_label().startswith("polish")]
    assert len(polish) == 1 and np.all(np.abs(polish[0].get_xdata() - 4) < 0.5)
    assert sorted(polish[0].get_ydata()) == sorted(POLISH)


def test_gradient_plot_without_polish_has_only_iteration_ticks():
    fig = _search_figure(gradient(NORMS, BOUNCES))
    assert tick_labels(fig.axes[0]) == ["0", "1", "2", "3"]


def test_many_iterations_get_integer_ticks():
    norms = [[1.0, 2.0]] * 20
    bounces = [[i % 3, 1] for i in range(21)]
    fig = _search_figure(gradient(norms, bounces, [1, 2]))
    labels = tick_labels(fig.axes[0])
    assert labels[-1] == "polish" and all(t.isdigit() for t in labels[:-1]) and len(labels) <= 10
    assert fig.axes[0].get_xticks()[-1] == 21


def test_every_start_and_the_best_are_in_the_legend():
    """The per-start lines have a legend entry (one for all starts), as do the best so far and the polish."""
    left = _search_figure(gradient(NORMS, BOUNCES, POLISH)).axes[0]
    texts = legend_texts(left)
    assert any(t.startswith("each start's true count") for t in texts)
    assert "best true count so far" in texts
    assert any(t.startswith("polish: 6 exact throws") for t in texts)
    starts = [line for line in left.lines if len(line.get_xdata()) == len(BOUNCES)
              and line.get_label() != "best true count so far"]
    assert len(starts) == 3
    assert np.array_equal(np.stack([s.get_ydata() for s in starts], axis=1), np.array(BOUNCES, float))


def test_gradient_plot_draws_both_thresholds():
    """EXPLODING and VANISHING as labelled horizontal lines of the gradient-norm panel."""
    right = _search_figure(gradient(NORMS, BOUNCES, POLISH)).axes[1]
    assert right.get_yscale() == "log"
    flat = {line.get_label(): line for line in right.lines if len(set(line.get_ydata())) == 1
            and len(line.get_ydata()) == 2}
    (vanishing,) = [line for label, line in flat.items() if label.startswith("vanishing")]
    (exploding,) = [line for label, line in flat.items() if label.startswith("exploding")]
    assert vanishing.get_ydata()[0] == VANISHING and exploding.get_ydata()[0] == EXPLODING
    assert any(t.startswith("vanishing: below 1e-06") for t in legend_texts(right))
    lo, hi = right.get_ylim()
    assert lo < VANISHING and hi > EXPLODING


def test_gradient_title_says_what_it_counts():
    """A start that dips below VANISHING once is counted as vanishing "at some iteration", not "at every
    iteration" (the count gradient_health reports)."""
    result = gradient(NORMS, BOUNCES, POLISH)
    title = _search_figure(result).axes[1].get_title()
    health = gradient_health(result)["starts"]
    assert f"starts whose gradient vanished at every iteration: {health['vanishing']}; at some iteration: 2" in title
    assert health["vanishing"] == 1
    assert f"starts whose gradient exploded at some iteration: {health['exploding']}" in title
    assert "of 3 starts" in title


def test_non_finite_and_zero_norms_are_drawn_at_the_edges():
    """A non-finite or exactly-zero norm has no place on a log axis: it is marked at the top or bottom
    edge (and said so), not dropped."""
    norms = [[None, 1.0], [0.0, 2.0]]
    right = _search_figure(gradient(norms, [[1, 2], [2, 3], [3, 4]])).axes[1]
    texts = legend_texts(right)
    assert "non-finite (drawn at the top edge)" in texts and "exactly 0 (drawn at the bottom edge)" in texts
    marks = {line.get_label(): line for line in right.lines}
    assert list(marks["non-finite (drawn at the top edge)"].get_xdata()) == [0]
    assert list(marks["exactly 0 (drawn at the bottom edge)"].get_xdata()) == [1]


def test_the_final_evaluation_is_said_to_have_no_gradient():
    right = _search_figure(gradient(NORMS, BOUNCES, POLISH)).axes[1]
    assert "no gradient: final evaluation and polish" in legend_texts(right)


def test_titles_give_the_throw_as_the_command_prints_it():
    """One decimal for the angles and the spin (which is named), two for the speed, as `jaxskip optimize`."""
    for result in (gradient(NORMS, BOUNCES, POLISH), exhaustive("grid", [0, 1, 2, 2])):
        title = _search_figure(result).axes[0].get_title()
        assert "speed 7.51 m/s, tilt 5.7°, attack 25.6°, spin 11.4 rev/s" in title, title


@pytest.mark.parametrize("make", [lambda: _search_figure(gradient(NORMS, BOUNCES, POLISH)),
                                  lambda: _search_figure(exhaustive("grid", [0] * 8 + [1, 1, 1, 2, 5, 13, 14, 21])),
                                  lambda: _sweep_figure(umin_result([3.0, 2.0, None], [0, 0, 0])),
                                  lambda: _sweep_figure(domain_result())],
                         ids=["gradient", "histogram", "umin", "domain"])
def test_legends_sit_outside_the_data(make):
    """The legends are placed below their panels: they cannot hide a line or a point."""
    fig = make()
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    assert legends
    for legend in legends:
        box, panel = legend.get_window_extent(renderer), legend.axes.get_window_extent(renderer)
        assert not box.overlaps(panel), (box, panel)


# --- sweeps -----------------------------------------------------------------------------------------

def test_umin_error_bars_are_the_bisection_bracket():
    """Each U_min is its bracket's top U: the true value lies in (U - resolution, U], drawn as an error
    bar of resolution below and nothing above; a tilt that bounces at the bracket's low end, or not at
    all, has no bar."""
    res = 0.25
    result = umin_result([3.0, 2.0, 0.5, None, 2.5], [0, 0, 3, 0, 0], res=res)
    ax = _sweep_figure(result).axes[0]
    (bars,) = [c for c in ax.containers if isinstance(c, ErrorbarContainer)]
    line, _, (cols,) = bars.lines
    assert list(line.get_xdata()) == [10.0, 20.0, 50.0] and list(line.get_ydata()) == [3.0, 2.0, 2.5]
    segments = np.array(cols.get_segments())
    np.testing.assert_allclose(segments[:, 0, 1], [3.0 - res, 2.0 - res, 2.5 - res])  # lower ends
    np.testing.assert_allclose(segments[:, 1, 1], [3.0, 2.0, 2.5])  # upper ends: the points themselves
    np.testing.assert_allclose(segments[:, :, 0], [[10.0, 10.0], [20.0, 20.0], [50.0, 50.0]])
    texts = legend_texts(ax)
    assert any("true U_min in (U − 0.25, U] m/s" in t for t in texts), texts
    assert "bounces at the bracket's low end: U_min ≤ 0.5 m/s" in texts
    assert "no bounce at the 10 speeds thrown up to 8 m/s" in texts
    assert any("lowest grid point: 30°, U_min ≤ 0.50 m/s" in t for t in texts), texts


def test_umin_best_tilt_states_its_bracket():
    ax = _sweep_figure(umin_result([3.0, 2.0, 2.5], [0, 0, 0], res=0.125)).axes[0]
    assert any("lowest grid point: 20°, U_min in (1.88, 2.00] m/s" in t for t in legend_texts(ax))
    assert "spin 65 rev/s (inert with the tilt held)" in ax.get_title() and "attack 20° at release" in ax.get_title()


def test_a_fine_bracket_is_shown_with_the_digits_the_command_prints():
    """A bracket of 0.0073 m/s (10 bisection steps over 7.5 m/s) is shown with four decimals, as
    `jaxskip sweep umin` prints it ("(1.7598, 1.7671] m/s"); with two it read (1.76, 1.77]."""
    ax = _sweep_figure(umin_result([2.5, 1.767, 1.9], [0, 0, 0], res=0.0073)).axes[0]
    assert any("U_min in (1.7597, 1.7670] m/s" in t for t in legend_texts(ax)), legend_texts(ax)


def test_domain_colour_bar_counts_in_integers():
    fig = _sweep_figure(domain_result())
    ax, cbar = fig.axes
    ticks = [t for t in cbar.get_yticks() if cbar.get_ylim()[0] <= t <= cbar.get_ylim()[1]]
    assert ticks == [0, 1, 2, 3, 4]
    assert cbar.get_ylabel() == "true bounce count [bounces]"
    assert "spin 65 rev/s" in ax.get_title() and "speed 3.5 m/s" in ax.get_title()


def test_umin_tilts_without_an_answer_say_why():
    """A tilt whose bisection met a throw cut off by the duration (or one that diverged) has no U_min: it was
    drawn as 'no bounce up to 8 m/s', the misreading its 'cut_off' count exists to prevent. Each reason now
    has its own mark and label; a tilt that never bounced keeps the old one."""
    result = dict(umin_result([None, 2.0, None, None], [0, 0, 0, 0]), cut_off=[0, 0, 2, 0], diverged=[0, 0, 0, 1])
    ax = _sweep_figure(result).axes[0]
    marks = {line.get_marker(): list(line.get_xdata()) for line in ax.get_lines() if line.get_marker() in "xX^"}
    assert marks == {"x": [10.0], "^": [30.0], "X": [40.0]}, marks
    texts = legend_texts(ax)
    assert any("still in play at the duration" in t for t in texts) and any("diverged" in t for t in texts), texts
    assert sum("no bounce at the 10 speeds thrown up to 8 m/s" in t for t in texts) == 1, texts


def test_domain_marks_the_points_the_duration_cut_off():
    """A grid point still skipping when the run stopped it (cut_off 1) has a count that is only a lower bound:
    it is marked where it lies, and the legend says so; a result without such points has no such mark."""
    result = dict(domain_result(), cut_off=[[0, 1, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0]])
    ax = _sweep_figure(result).axes[0]
    marks = [line for line in ax.get_lines() if line.get_marker() == "^"]
    assert len(marks) == 1 and list(marks[0].get_xdata()) == [10.0] and list(marks[0].get_ydata()) == [15.0]
    assert any("count is a lower bound" in t for t in legend_texts(ax)), legend_texts(ax)
    ax = _sweep_figure(domain_result()).axes[0]
    assert not [line for line in ax.get_lines() if line.get_marker() == "^"]


def test_domain_has_tilt_on_x_like_the_umin_panel_and_the_notebook():
    """`jaxskip sweep domain --plot` drew tilt on y while its U_min picture and the magic-angle notebook
    draw it on x; now each cell sits at (tilt, attack) with its own count."""
    from matplotlib.collections import QuadMesh

    ax = _sweep_figure(domain_result()).axes[0]
    assert ax.get_xlabel().startswith("tilt α") and ax.get_ylabel() == "attack at release [deg]"
    mesh = next(c for c in ax.collections if isinstance(c, QuadMesh))
    counts = np.asarray(mesh.get_array()).reshape(4, 3)   # rows: attacks 0..45, columns: tilts 10..30
    assert counts[1, 0] == 4 and counts[2, 1] == 1 and counts[1, 2] == 1
    np.testing.assert_array_equal(counts, np.asarray(domain_result()["bounces"]).T)
    assert ax.get_xlim()[0] < 10.0 < 30.0 < ax.get_xlim()[1] and ax.get_ylim()[0] < 0.0 < 45.0 < ax.get_ylim()[1]


DIMENSIONLESS = {"iteration", "number of throws", "number of throws (log scale)"}


@pytest.mark.parametrize("make", [lambda: _search_figure(gradient(NORMS, BOUNCES, POLISH)),
                                  lambda: _search_figure(exhaustive("grid", [0, 1, 1, 4])),
                                  lambda: _sweep_figure(umin_result([3.0, 2.0, None], [0, 0, 0])),
                                  lambda: _sweep_figure(domain_result())],
                         ids=["gradient", "grid", "umin", "domain"])
def test_every_axis_label_has_units(make):
    """Each axis label names its unit in brackets, or is a plain count (iterations, throws)."""
    for ax in make().axes:
        for label in (ax.get_xlabel(), ax.get_ylabel()):
            if label:
                assert label in DIMENSIONLESS or ("[" in label and label.endswith("]")), label


def test_plot_functions_write_their_picture(tmp_path):
    """The public functions keep their behaviour: they save a picture to the path and return None."""
    for name, result, plot in [("search.png", gradient(NORMS, BOUNCES, POLISH), plot_search),
                               ("grid.svg", exhaustive("grid", [0, 1, 2]), plot_search),
                               ("umin.png", umin_result([3.0, 2.0, 2.5], [0, 0, 0]), plot_sweep),
                               ("domain.pdf", domain_result(), plot_sweep)]:
        assert plot(result, tmp_path / name) is None
        assert (tmp_path / name).stat().st_size > 1000


def test_a_picture_path_needs_a_format_suffix(tmp_path):
    """(session 32, a review) a path without a suffix was saved with .png added, a file never named: refused
    before drawing, as plot_throw refuses it."""
    from jaxskip import ParameterError

    for result, plot in [(gradient(NORMS, BOUNCES, POLISH), plot_search), (umin_result([3.0, 2.0, 2.5], [0, 0, 0]),
                                                                           plot_sweep)]:
        with pytest.raises(ParameterError, match="path must end in a picture format matplotlib writes"):
            plot(result, tmp_path / "picture")
    assert not any(tmp_path.iterdir())


def test_a_local_search_with_diverged_throws_is_drawn():
    """(session 32, a review) a local search lists a diverged throw with count -1 (DIVERGED_SCORE): its
    histogram met np.bincount's "no negative elements" ValueError. Drawn from the others, the diverged
    ones said in the legend; a grid's title counts every throw."""
    counts = [0, 2, 2, 5, -1, -1]
    history = [{"iteration": 0, "phase": "polish", "bounces": counts, "distance": [1.0] * 6, "objective": None,
                "best": 5, "nonfinite": 0, "points": {}}]
    r = SearchResult("local", BEST, 5, history, make_box(), 1.0, 6, 0, best_distance=3.21, diverged=2)
    (ax,) = _search_figure(r).axes
    heights = {round(p.get_x() + p.get_width() / 2): p.get_height() for p in ax.patches}
    assert {k: v for k, v in heights.items() if v} == {0: 1, 2: 2, 5: 1}
    assert any("4 throws; 2 more diverged, not drawn" in t for t in legend_texts(ax)), legend_texts(ax)
    assert "6 throws" in ax.get_title()
    grid = exhaustive("grid", [1] * 79)      # 3^4 = 81 grid throws, 2 of which diverged
    grid = SearchResult("grid", BEST, 1, grid.history, make_box(), 1.0, 81, 0, best_distance=3.21, diverged=2)
    assert "3 per searched parameter, 81 throws" in _search_figure(grid).axes[0].get_title()


def test_a_tie_and_a_scan_that_is_not_monotone_are_drawn_as_such():
    """(2026-12-06, a review) a tie for the lowest U_min was drawn as 'lowest grid point: 10°' beside a parabola
    star the text output refused to give; now every tied tilt is marked as a tie. A tilt whose scan was not
    monotone is ringed."""
    result = dict(umin_result([3.0, 2.0, 2.0, 2.5], [0, 0, 0, 0]), tied_tilts=[20.0, 30.0], monotone=[1, 1, 1, 0])
    ax = _sweep_figure(result).axes[0]
    texts = legend_texts(ax)
    assert any(t.startswith("no single minimum: 20, 30° tie, U_min in (1.75, 2.00] m/s") for t in texts), texts
    assert not any("lowest grid point" in t for t in texts), texts
    assert "a faster throw failed to bounce here: the lowest bouncing speed of a scan, bisected" in texts
    dashed = [ln.get_xdata()[0] for ln in ax.get_lines() if ln.get_linestyle() == "--"]
    assert dashed == [20.0, 30.0]


@pytest.mark.parametrize("tilts, attacks, b", [([10.0, 20.0], [10.0], [[4], [2]]), ([15.0], [0.0, 10.0, 20.0], [[0, 3, 1]]),
                                               ([20.0, 10.0], [10.0], [[0], [0]])],
                         ids=["one-attack", "one-tilt", "all-zero-unsorted"])
def test_a_one_row_domain_is_drawn_with_whole_count_ticks(tilts, attacks, b):
    """(2026-12-07, a review) `jaxskip sweep domain --tilts 10,20 --attacks 10 --plot` drew empty axes beside a
    colour bar: with one tilt or one attack, shading='nearest' had no spacing to size a cell by. Every grid
    point is a cell now (a lone value 2 deg wide); with every count 0 the bar read -0.4, -0.2, ... 'bounces'."""
    from matplotlib.collections import QuadMesh

    spec = {"kind": "domain", "tilts": tilts, "attacks": attacks, "speed": 3.5, "spin": 65.0, "stone": "clanet",
            "attitude": "fixed"}
    fig = _sweep_figure({"spec": spec, "bounces": b, "first_contact_time": [[None] * len(attacks)] * len(tilts)})
    ax, bar = fig.axes
    (mesh,) = [c for c in ax.collections if isinstance(c, QuadMesh)]
    cells = np.asarray(mesh.get_array()).reshape(len(attacks), len(tilts))
    order = np.argsort(tilts)
    np.testing.assert_array_equal(cells, np.asarray(b, dtype=float)[order].T)
    x0, x1 = ax.get_xlim()
    assert x0 < min(tilts) and x1 > max(tilts)
    fig.draw_without_rendering()
    ticks = [float(t) for t in bar.get_yticks()]
    assert ticks and all(t == int(t) and 0 <= t <= max(map(max, b)) for t in ticks), ticks


def test_cut_off_counts_are_drawn_as_lower_bounds_and_equal_counts_get_whole_ticks():
    """(2026-12-07, a review) a search whose best throw the duration cut off drew its count as the final, "true"
    one (the CLI warned; the picture did not), and a search whose counts were all equal got ticks of
    4.74...5.22 or -0.045...0.045 bounces."""
    import dataclasses

    result = dataclasses.replace(exhaustive("random", [0, 0, 1, 2]), cut_off=3, best_cut_off=True)
    ax = _search_figure(result).axes[0]
    assert "cut off: a lower bound" in ax.get_title()
    assert any("3 throws cut off while in play" in t.get_text() for t in ax.get_legend().get_texts())
    flat = gradient([[1.0, 2.0]], [[5, 5], [5, 5]])
    ax = _search_figure(flat).axes[0]
    low, high = ax.get_ylim()
    ticks = [t for t in ax.get_yticks() if low <= t <= high]
    assert high - low >= 3 and len(ticks) >= 2 and all(float(t).is_integer() for t in ticks), (low, high, ticks)
    assert "cut off" not in ax.get_title()


def test_umin_line_joins_measured_values_only():
    """(2026-12-07, a review) the U_min line joined an upper bound (a tilt that bounces at the bracket's low end)
    to the measured values, drawing a slope no bisection measured."""
    result = umin_result([0.5, 2.0, 3.0], [1, 0, 0])
    ax = _sweep_figure(result).axes[0]
    line = next(ln for ln in ax.get_lines() if ln.get_linestyle() == "-" and len(ln.get_xdata()) == 3)
    y = np.asarray(line.get_ydata(), dtype=float)
    assert np.isnan(y[0]) and np.allclose(y[1:], [2.0, 3.0]), y
