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
    _number_contacts(side, fig, xs, xlim)
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


def test_a_last_contact_on_top_of_others_displaces_them():
    xs = list(np.linspace(1.0, 1.05, 30))          # far too dense for three rows
    labels, boxes = _numbers(xs)
    for (la, a), (lb, b) in itertools.combinations(zip(labels, boxes), 2):
        assert not a.overlaps(b), (la, lb)
    assert "1" in labels and "30" in labels
