"""The side view's contact numbers stay readable when contacts crowd together."""

import itertools

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from jaxskip.plotting import _number_contacts  # noqa: E402


def _numbers(xs, xlim=(-0.2, 2.2)):
    fig, side = plt.subplots(figsize=(10, 3.5))
    side.set_xlim(*xlim)
    side.set_ylim(-2.0, 3.0)
    _number_contacts(side, xs, xlim)
    fig.canvas.draw()
    texts = [t for t in side.texts]
    boxes = [t.get_window_extent() for t in texts]
    labels = [t.get_text() for t in texts]
    plt.close(fig)
    return labels, boxes


def test_crowded_contact_numbers_do_not_overlap_and_the_last_is_shown():
    # the default throw's pattern: one long hop, then 17 contacts 1.5-4 cm apart
    xs = [0.01, 0.95, 1.04, 1.15, 1.25, 1.31] + list(np.linspace(1.37, 1.68, 13))
    labels, boxes = _numbers(xs)
    for (la, a), (lb, b) in itertools.combinations(zip(labels, boxes), 2):
        assert not a.overlaps(b), (la, lb)
    assert "1" in labels and str(len(xs)) in labels
    assert len(labels) == len(xs)       # staggered rows number every contact (one row held 13 of 19)


def test_sparse_contact_numbers_are_all_in_one_row():
    xs = [0.0, 0.5, 1.0, 1.5, 2.0]
    labels, boxes = _numbers(xs)
    assert labels == ["1", "2", "3", "4", "5"]
    assert len({round(b.y0, 3) for b in boxes}) == 1


def test_too_many_contacts_are_numbered_by_a_visible_rule():
    """Where not every number fits, every 5th (10th, ...) is numbered, with the first and the last."""
    xs = list(np.linspace(1.0, 1.5, 60))           # 60 contacts in 0.5 m: three rows cannot hold them all
    labels, boxes = _numbers(xs)
    for (la, a), (lb, b) in itertools.combinations(zip(labels, boxes), 2):
        assert not a.overlaps(b), (la, lb)
    numbers = sorted(int(v) for v in labels)
    assert numbers[0] == 1 and numbers[-1] == 60
    inner = numbers[1:-1]
    step = inner[1] - inner[0]
    assert step in (5, 10, 20) and inner == list(range(step, 60, step))[:len(inner)]
    assert inner[-1] >= 60 - step                    # none skipped on the way


def test_the_first_and_the_last_contact_are_always_numbered():
    xs = list(np.linspace(1.0, 1.02, 30))          # far too dense for any rule but first and last
    labels, boxes = _numbers(xs)
    for (la, a), (lb, b) in itertools.combinations(zip(labels, boxes), 2):
        assert not a.overlaps(b), (la, lb)
    assert "1" in labels and "30" in labels


# --- the side view's curves and the water pictures (jaxskip/plotting.py) ---------------------------


import pytest  # noqa: E402

from jaxskip import SimConfig, Throw, simulate  # noqa: E402
from jaxskip.plotting import _arc_path, _elevation_limit, _frame_durations, _in_contact, plot_throw  # noqa: E402


@pytest.fixture(scope="module")
def held_disk():
    """Clanet's disk, attitude held, the default throw: 7 bounces, and a last contact holding a hop that
    clears the water by less than the bounce clearance."""
    return simulate(Throw.from_degrees(), stone="clanet", config=SimConfig(attitude="fixed"))


def _runs(mask):
    m = np.asarray(mask, int)
    return int(np.sum(np.diff(np.concatenate([[0], m])) == 1))


def test_the_red_contact_line_has_one_stretch_per_logged_contact(held_disk):
    r = held_disk
    wet_steps = np.asarray(r.trajectory["wetted_area"]) > 0
    assert _runs(wet_steps) > len(r.contacts)          # a sub-clearance hop splits a contact's wet steps
    times, _ = _arc_path(r)
    assert _runs(_in_contact(r, times)) == len(r.contacts)
    assert _runs(_in_contact(r)) == len(r.contacts)


def test_flights_are_drawn_along_their_parabola(held_disk):
    r = held_disk
    t = np.asarray(r.trajectory["time"])
    x = np.asarray(r.trajectory["position"])
    v = np.asarray(r.trajectory["velocity"])
    times, path = _arc_path(r)
    # every recorded step is on the drawn path, at its own time
    idx = np.searchsorted(times, t)
    np.testing.assert_array_equal(times[idx], t)
    np.testing.assert_allclose(path[idx], x, rtol=0, atol=1e-12)
    # the first flight's apex: the parabola's, which none of the flight's few steps lands on
    c0, c1 = r.contacts[0], r.contacts[1]
    k = int(np.searchsorted(t, c0.t_end))                 # the first step after the stone left the water
    g = float(r.water.gravity)
    apex = x[k, 2] + v[k, 2] ** 2 / (2 * g)
    flight = (times > c0.t_end) & (times < c1.t_start)
    assert path[flight, 2].max() == pytest.approx(apex, abs=2e-5)
    chords = np.interp(times[flight], t, x[:, 2])          # what joining the steps by lines would draw
    assert np.max(np.abs(path[flight, 2] - chords)) > 3e-4   # chords sag ~0.5 mm off the 3 cm arc


def test_a_straight_throw_gets_a_readable_sideways_axis(held_disk):
    fig = plot_throw(held_disk)
    side, top = fig.axes[:2]
    lo, hi = top.get_ylim()
    assert hi - lo >= 2.0 and lo <= 0.0 <= hi            # at least +-1 cm around a line drifting by 1e-15 cm
    assert top.yaxis.get_offset_text().get_text() == ""
    assert side.get_xlim() == top.get_xlim()
    import matplotlib.pyplot as plt
    plt.close(fig)


def test_frame_durations_follow_simulated_time():
    times = [0.0, 0.01, 0.02, 0.12, 0.13, 0.14]        # a 0.1 s flight between 10 ms frames
    ms = _frame_durations(times, fps=20)
    assert len(ms) == len(times) and all(m % 10 == 0 for m in ms)
    assert ms[2] == max(ms) and ms[2] >= 5 * ms[0]       # the flight's frame is held ~10x longer
    assert abs(np.mean(ms) - 1000 / 20) <= 10
    assert _frame_durations([0.0, 0.0, 0.0], fps=10) == [100, 100, 100]
    assert min(_frame_durations([0.0, 1e-6, 1.0], fps=50)) == 20


def test_the_colour_scale_is_a_percentile_not_a_spike():
    depth = 0.02
    calm = np.full((32, 32), depth) + 1e-3 * np.sin(np.arange(1024).reshape(32, 32))
    spike = calm.copy()
    spike[3, 3] = depth + 0.1                             # one 100 mm column
    frames = [(0.0, (0, 0), calm, None, None), (0.1, (0, 0), spike, None, None)]
    lim = _elevation_limit(frames, depth)
    assert lim == pytest.approx(np.percentile(np.abs(np.stack([calm, spike]) - depth), 99.5) * 1e3)
    assert 0.9 < lim <= 1.0                               # the ripples' 1 mm, not the spike's 100 mm
    # still water: a scale of 0.1 um, not its rounding noise (+-1e-6 mm before 2026-12-07, a review)
    assert _elevation_limit([(0.0, (0, 0), np.full((4, 4), depth) + 1e-12, None, None)], depth) == 1e-4


def test_contacts_beyond_the_log_are_still_drawn_in_contact():
    """With max_contacts=5 the default throw logs 5 of its contacts; the rest of its wet steps are
    still drawn in contact (they were drawn as flight)."""
    r = simulate(Throw.from_degrees(), stone="paper", config=SimConfig(max_contacts=5))
    assert len(r.contacts) == 5 < r.n_contacts
    wet_steps = np.asarray(r.trajectory["wetted_area"]) > 0
    drawn = _in_contact(r)
    assert np.all(drawn[wet_steps])                        # every wet step is drawn in contact
    after = np.asarray(r.trajectory["time"]) > r.contacts[-1].t_end
    assert np.array_equal(drawn[after], wet_steps[after])
    fig = plot_throw(r)
    labels = fig.axes[0].get_legend_handles_labels()[1]
    assert any(f"the first 5 of {r.n_contacts} logged" in label for label in labels)
    import matplotlib.pyplot as plt
    plt.close(fig)


def test_steps_of_dt_are_not_filled_in_as_flights():
    """A coarse dt (2 ms, with flights stepped at dt): no step is a jump, so the drawn path is the
    recorded steps, not parabolas through the contacts."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")                   # the accuracy warning for dt > 1 ms
        r = simulate(Throw.from_degrees(), stone="paper", config=SimConfig(dt=2e-3, flight="step"))
    times, path = _arc_path(r)
    np.testing.assert_array_equal(times, np.asarray(r.trajectory["time"], dtype=np.float64))
    np.testing.assert_array_equal(path, np.asarray(r.trajectory["position"], dtype=np.float64))


def test_the_side_view_draws_into_subfigures():
    import matplotlib.pyplot as plt

    r = simulate(Throw.from_degrees(), stone="paper", config=SimConfig(max_contacts=5))
    fig = plt.figure(figsize=(12, 4))
    left, right = fig.subfigures(1, 2)
    plot_throw(r, ax=tuple(left.subplots(2, 1)))
    plot_throw(r, ax=tuple(right.subplots(2, 1)))
    side = left.axes[0]
    assert "\n" in side.get_title()                       # a 6-inch-wide figure's half: the title wraps
    fig.canvas.draw()
    plt.close(fig)


def test_a_narrow_side_views_legend_stays_inside_it(held_disk):
    """(2026-12-07, a review) In a grid of panels (notebooks/optimize_throw.py: three columns of 16.5 inches) the
    side view's one-row legend ran ~90 px past the axes' right edge; it is made compact where it would."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 3, figsize=(13.0, 5.5), height_ratios=[2.2, 1], layout="constrained")
    plot_throw(held_disk, ax=(axes[0, 0], axes[1, 0]))
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    legend, box = axes[0, 0].get_legend().get_window_extent(renderer), axes[0, 0].get_window_extent(renderer)
    assert box.x0 <= legend.x0 and legend.x1 <= box.x1, (legend, box)
    plt.close(fig)


def test_the_contact_the_stone_ended_in_is_marked(held_disk):
    """Clanet's disk makes 7 bounces in 8 contacts and sinks in the 8th: numbered "8 (sank)", so the
    numbers do not read as 8 bounces under a title of 7."""
    r = held_disk
    assert (r.bounces, r.n_contacts, r.outcome) == (7, 8, "sank")
    fig = plot_throw(r)
    labels = [t.get_text() for t in fig.axes[0].texts]
    assert labels[-1] == "8 (sank)", labels  # the last contact, the one it sank in
    assert sum("(" in label for label in labels) == 1
    import matplotlib.pyplot as plt
    plt.close(fig)


def test_pictures_refuse_bad_arguments_by_name(held_disk):
    """A frame index out of range, a stone given by name, a batch result, a frame rate GIF viewers cannot
    show: each named (they ended in an IndexError, AttributeError or a silently slower animation)."""
    import dataclasses

    from jaxskip import ParameterError, clanet_disk, paper_stone, rigid_stone
    from jaxskip.plotting import animate_throw, plot_throw, plot_water

    stone = rigid_stone(clanet_disk(), density=2700.0)
    one = (0.0, np.zeros(2), np.full((8, 8), 0.02), np.array([0.0, 0.0, 0.01]), np.array([1.0, 0.0, 0.0, 0.0]))
    wet = dataclasses.replace(held_disk, field={"depth": 0.02, "spacing": 0.01, "shape": [8, 8], "frames": [one]})
    for frame, message in ((999, r"frame must be .*\[-1, 0\]"), (1.5, "frame must be an integer")):
        with pytest.raises(ParameterError, match=message):
            plot_water(wet, stone, frame=frame)
    with pytest.raises(ParameterError, match="stone must be the jaxskip.RigidStone that was thrown"):
        plot_water(wet, "clanet")
    # (2026-12-07, a review) another stone than the thrown one drew another footprint, in silence; None is the
    # result's own
    with pytest.raises(ParameterError, match="stone is not the stone this throw was simulated with"):
        plot_water(wet, rigid_stone(paper_stone(), density=2650.0))
    fig = plot_water(wet, None)
    # (stop 48, a review) the default frame says why it was drawn; the 3-D view's exaggeration is named as one
    assert "the most disturbed moment" in fig.axes[0].get_title(), fig.axes[0].get_title()
    assert "tall)" in [a for a in fig.axes if hasattr(a, "get_zlabel")][0].get_zlabel()
    plt.close(fig)
    fig = plot_water(wet, None, frame=0)
    assert "most disturbed" not in fig.axes[0].get_title()
    plt.close(fig)
    with pytest.raises(ParameterError, match=r"the path came second, as the stone \('x.gif'\); give "
                                             r"animate_throw\(result, None, 'x.gif'\)"):
        animate_throw(wet, "x.gif")   # (a raw TypeError: a missing argument 'path')
    with pytest.raises(ParameterError, match="result must be a jaxskip ThrowResult .*got dict"):
        plot_throw({"trajectory": None})
    with pytest.raises(ParameterError, match=r"fps must be in \(0, 50\]"):
        animate_throw(wet, stone, "x.gif", fps=60)


def test_a_picture_path_needs_a_format_suffix(held_disk, tmp_path):
    """(session 32, a review) plot_throw(r, "h2") wrote h2.png, a file never named; an unknown suffix failed
    only after the figure was drawn. Both refused before drawing, naming the formats; .jpg is matplotlib's."""
    from jaxskip import ParameterError

    for bad in ("h2", str(tmp_path / "h2"), tmp_path / ".png", "h2.tx"):
        with pytest.raises(ParameterError, match=r"path must end in a picture format matplotlib writes \(.*png"):
            plot_throw(held_disk, bad)
    assert not any(tmp_path.iterdir())
    plot_throw(held_disk, tmp_path / "h2.jpg")
    assert (tmp_path / "h2.jpg").read_bytes()[:2] == b"\xff\xd8"   # a JPEG


def test_an_animation_into_a_missing_folder_is_refused_before_drawing(held_disk, tmp_path, monkeypatch):
    """(2026-12-06, a review) animate_throw drew every frame, then met a raw FileNotFoundError (no folder) or
    IsADirectoryError (a folder named x.gif); both are refused first, by name."""
    import dataclasses

    import jaxskip.plotting as plotting
    from jaxskip import ParameterError, clanet_disk, rigid_stone

    stone = rigid_stone(clanet_disk(), density=2700.0)
    one = (0.0, np.zeros(2), np.full((8, 8), 0.02), np.array([0.0, 0.0, 0.01]), np.array([1.0, 0.0, 0.0, 0.0]))
    wet = dataclasses.replace(held_disk, field={"depth": 0.02, "spacing": 0.01, "shape": [8, 8], "frames": [one]})
    monkeypatch.setattr(plotting, "_arc_path", lambda *a: pytest.fail("drew before checking the path"))
    with pytest.raises(ParameterError, match=r"path: the folder .*nowhere' of .*x.gif' does not exist"):
        plotting.animate_throw(wet, stone, tmp_path / "nowhere" / "x.gif")
    (tmp_path / "d.gif").mkdir()
    with pytest.raises(ParameterError, match=r"path must name a file, got the folder .*d.gif'"):
        plotting.animate_throw(wet, stone, tmp_path / "d.gif")
    with pytest.raises(ParameterError, match=r"path: the folder .*nowhere' of .*x.png' does not exist"):
        plotting.plot_water(wet, stone, tmp_path / "nowhere" / "x.png")


def test_water_pictures_word_a_small_scale_and_the_rest_level(held_disk):
    """(2026-12-07, a review) plot_water's 3-D title read 'clipped at ±0 mm' for a surface disturbed by
    micrometres (the scale printed with no decimals), and its still water took the colour map's darkest blue
    (each frame normalised to its own range); plot_throw of a field run labelled z = 0 'water surface' where the
    field's surface moves."""
    import dataclasses

    from jaxskip import clanet_disk, rigid_stone
    from jaxskip.plotting import plot_water

    stone = rigid_stone(clanet_disk(), density=2700.0)
    height = np.full((8, 8), 0.02)
    height[3, 4] += 4e-6                               # 4 um: a drop's worth
    one = (0.0, np.zeros(2), height, np.array([0.0, 0.0, 0.01]), np.array([1.0, 0.0, 0.0, 0.0]))
    wet = dataclasses.replace(held_disk, field={"depth": 0.02, "spacing": 0.01, "shape": [8, 8], "frames": [one]})
    fig = plot_water(wet, stone)
    title = fig.axes[-1].get_title()
    assert "clipped at ±0.0055 mm" in title, title    # twice the colour scale, the 99.5th percentile: 2.7 um
    surface = [c for c in fig.axes[-1].collections if hasattr(c, "norm") and c.get_array() is not None][0]
    assert surface.norm.vmin == pytest.approx(-surface.norm.vmax) and surface.norm.vmax == pytest.approx(0.0055, rel=0.01)
    plt.close(fig)
    fig = plot_throw(wet)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert "water at rest (the field's surface is not drawn)" in labels and "water surface" not in labels, labels
    plt.close(fig)
    fig = plot_throw(held_disk)
    assert "water surface" in [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    plt.close(fig)


def test_the_side_views_title_gives_a_short_throws_distance():
    """(2026-12-07, a review) the title rounded the distance to 0.1 m: a throw of a few centimetres read "0.0 m"."""
    result = simulate(Throw.from_degrees(speed=0.5))
    fig = plot_throw(result)
    title = " ".join([fig.get_suptitle()] + [a.get_title() for a in fig.axes])
    plt.close(fig)
    assert f"{result.distance:.3g} m" in title and result.distance < 0.1 and "0.0 m" not in title, title


def test_the_side_view_says_how_much_it_stretches_heights():
    """(2026-12-07, a review) heights in cm against metres downrange drew 3-5° bounces as 45-60° slopes, unsaid:
    the axis label gives the stretch, measured from the axes on the page (about 11 for the default throw)."""
    import re

    from jaxskip.plotting import _vertical_stretch

    fig = plot_throw(simulate())
    side = fig.axes[0]
    said = re.search(r"drawn ×(\d+) tall", side.get_ylabel())
    assert said and int(said.group(1)) == round(_vertical_stretch(side)) and 5 < int(said.group(1)) < 30
    plt.close(fig)
    # (stop 47, a review) a steep, short throw drawn flattened (×0.42: a 63° climb looked shallow) said nothing
    fig = plot_throw(simulate(Throw.from_degrees(speed=1.0, attack=60.0)))
    side = fig.axes[0]
    said = re.search(r"drawn ×(0\.\d+) tall", side.get_ylabel())
    assert said and float(said.group(1)) == pytest.approx(_vertical_stretch(side), abs=0.005), side.get_ylabel()
    assert _vertical_stretch(side) < 1 / 1.5
    plt.close(fig)


def test_the_side_views_title_gives_a_heading_other_than_zero():
    """(stop 47, an animator's review) a throw along +y (heading 90°) had the same title as one along +x, while the
    side view is drawn along the heading and the exported motion runs along y."""
    titles = {}
    for heading in (0.0, 90.0):
        fig = plot_throw(simulate(Throw.from_degrees(heading=heading), config=SimConfig(duration=0.05)))
        titles[heading] = " ".join(a.get_title() for a in fig.axes)
        plt.close(fig)
    assert "heading 90.0°" in titles[90.0] and "heading" not in titles[0.0], titles


def test_animation_frames_share_one_palette():
    """(2026-12-07, a review) each GIF frame got its own palette: a fixed pixel of the colour bar took 24 colours over
    36 frames, and the colour bar flickered. The frames share the palette of their first, middle and last now."""
    from PIL import Image

    from jaxskip.plotting import _one_palette

    rng = np.random.default_rng(0)
    ramp = np.linspace(0, 255, 64).astype(np.uint8)
    frames = []
    for k in range(5):   # a fixed colour bar (the ramp) beside changing noise
        a = np.zeros((64, 96, 3), np.uint8)
        a[:, :32] = ramp[:, None, None]
        a[:, 32:] = rng.integers(0, 256, (64, 64, 3))
        frames.append(Image.fromarray(a))
    out = _one_palette(frames)
    assert all(im.mode == "P" and im.getpalette() == out[0].getpalette() for im in out)
    bars = [np.asarray(im.convert("RGB"))[:, :32] for im in out]
    assert all(np.array_equal(b, bars[0]) for b in bars)          # the bar is drawn alike in every frame
