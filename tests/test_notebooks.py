"""Every notebook runs top to bottom in quick mode (JAXSKIP_QUICK=1) and writes its figure; what the
notebooks found is pinned here."""

import os
import re
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NOTEBOOKS = sorted(f for f in os.listdir(os.path.join(ROOT, "notebooks")) if f.endswith(".py"))


# Notebooks whose quick mode is bound by running, not compiling: they run at XLA's shipped
# optimisation level (conftest.py lowers it for the compile-bound rest; session 20, 2-core AVX2:
# magic_angle 31 s against 78 s at the lowered level, bocquet 29 s against 59 s).
RUN_BOUND = {"magic_angle.py", "bocquet.py"}


def run_notebook(name, out):
    from conftest import TEST_OPT_FLAG

    env = {**os.environ, "JAXSKIP_QUICK": "1", "JAXSKIP_NOTEBOOK_OUT": str(out),
           "PYTHONPATH": ROOT + os.pathsep + os.environ.get("PYTHONPATH", "")}
    if name in RUN_BOUND:
        env["XLA_FLAGS"] = env.get("XLA_FLAGS", "").replace(TEST_OPT_FLAG, "").strip()
    # Run as a Jupyter kernel runs the cells: without ``__file__`` (every notebook once needed it and
    # failed in its first cell there).
    path = os.path.join(ROOT, "notebooks", name)
    code = f"path = {path!r}; exec(compile(open(path).read(), path, 'exec'), {{'__name__': '__main__'}})"
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=str(out),
                       timeout=600)
    assert p.returncode == 0, p.stderr[-3000:]
    return p.stdout


@pytest.mark.parametrize("value, quick", [("1", True), ("true", True), ("TRUE", True), ("Yes", True), ("0", False),
                                          ("false", False), ("No", False), ("", False), (None, False)])
def test_quick_mode_reads_the_usual_spellings(value, quick, tmp_path, monkeypatch):
    """``JAXSKIP_QUICK=true`` is quick (it once ran the full notebook silently: only "1" was)."""
    from jaxskip.notebook import notebook_mode

    monkeypatch.setenv("JAXSKIP_NOTEBOOK_OUT", str(tmp_path))
    if value is None:
        monkeypatch.delenv("JAXSKIP_QUICK", raising=False)
    else:
        monkeypatch.setenv("JAXSKIP_QUICK", value)
    assert notebook_mode("example").quick is quick


@pytest.mark.parametrize("value", ["2", "quick", "on", "y"])
def test_quick_mode_refuses_other_values(value, tmp_path, monkeypatch):
    from jaxskip.notebook import notebook_mode

    monkeypatch.setenv("JAXSKIP_NOTEBOOK_OUT", str(tmp_path))
    monkeypatch.setenv("JAXSKIP_QUICK", value)
    with pytest.raises(ValueError, match="JAXSKIP_QUICK"):
        notebook_mode("example")


def test_unwritable_figure_folder_is_refused_at_set_up(tmp_path, monkeypatch):
    """An existing folder that cannot be written fails at set-up, naming JAXSKIP_NOTEBOOK_OUT (it failed
    at ``savefig``, after the whole computation, with a bare PermissionError)."""
    from jaxskip.notebook import notebook_mode

    folder = tmp_path / "read-only"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        if os.access(folder, os.W_OK):   # root writes anyway: a folder nobody can create files in
            if not os.path.isdir("/proc"):
                pytest.skip("running as root without /proc: no unwritable folder to test with")
            folder = "/proc"
        monkeypatch.setenv("JAXSKIP_NOTEBOOK_OUT", str(folder))
        monkeypatch.delenv("JAXSKIP_QUICK", raising=False)
        with pytest.raises(OSError, match="JAXSKIP_NOTEBOOK_OUT"):
            notebook_mode("example")
        assert not [f for f in os.listdir(tmp_path / "read-only")]   # (the probe file is not left behind)
    finally:
        (tmp_path / "read-only").chmod(0o755)


def test_missing_figure_folder_is_made(tmp_path, monkeypatch):
    from jaxskip.notebook import notebook_mode

    monkeypatch.setenv("JAXSKIP_NOTEBOOK_OUT", str(tmp_path / "a" / "b"))
    run = notebook_mode("example")
    assert os.path.isdir(run.out) and os.listdir(run.out) == []


@pytest.mark.parametrize("name", NOTEBOOKS)
def test_notebook_runs_in_quick_mode(name, tmp_path):
    out = run_notebook(name, tmp_path)
    figure = tmp_path / (name[:-3] + ".png")
    assert figure.exists() and figure.stat().st_size > 10_000, out[-2000:]
    if name == "bocquet.py":
        # The friction ratio measured from the mesh simulator's impulse is Bocquet's C~/C (5 %).
        m = re.search(r"mu = C~/C = ([\d.]+); measured from the mesh impulse ([\d.]+)", out)
        assert m and abs(float(m.group(2)) / float(m.group(1)) - 1) < 0.05, out
        # Mesh and reduced model give the same minimum speed on the quick grid.
        m = re.search(r"U_min: mesh ([\d.]+) m/s, reduced ([\d.]+) m/s", out)
        assert m and m.group(1) == m.group(2), out
    if name == "speed_vs_accuracy.py":
        # The default configuration lies on, or within 10 % of, the Pareto front.
        m = re.search(r"front's best at no more cost [\d.]+ \(([+-]\d+)%", out)
        assert m and int(m.group(1)) <= 10, out
        # The height field changes the contact: flat water's first contact is > 20 % off the field's.
        m = re.search(r"flat water \(library default\) .*first contact error ([\d.]+)%", out)
        assert m and float(m.group(1)) > 20.0, out
    if name == "magic_angle.py":
        # Tilt held, Bocquet's law: U_min is lowest at 10-20 deg, near Clanet's 2.5 m/s (30 %), and more
        # than doubles by 50 deg; the free body at 65 rev/s follows the fixed-tilt curve within 25 % there.
        def curve(label):
            line = re.search(label + r".*?U_min = (.*?) m/s", out).group(1)
            return {float(t): float(u) for t, u in re.findall(r"([\d.]+)°: ([\d.]+)", line)}
        fixed, free = curve(r"fixed \(Bocquet law\)"), curve(r"free  \(Bocquet law\)")
        low = min(fixed, key=fixed.get)
        assert low in (10.0, 20.0) and abs(fixed[low] / 2.5 - 1) < 0.3, out
        assert fixed[50.0] > 2 * fixed[20.0], out
        assert all(abs(free[t] / fixed[t] - 1) < 0.25 for t in (10.0, 20.0)), out
    if name == "optimize_throw.py":
        # Started from the clumsy throw, the gradient search's own path gains bounces.
        path = [int(v) for v in re.search(r"the poor throw's own path: \[(.*?)\]", out).group(1).split(",")]
        assert path[-1] > path[0], out
    if name == "energy.py":
        # The default (body-velocity) law adds energy to the default throw (4.63 -> 7.98 J); the other
        # velocity options and the held tilt never do (rises of rounding size only).
        runs = {m.group(1): (float(m.group(2)), float(m.group(3)), float(m.group(4))) for m in re.finditer(
            r"^(.*?): \d+ bounces .*?energy ([\d.]+) J at release, peak ([\d.]+) J, .*? step ([-\d.e+]+) J$", out, re.M)}
        assert len(runs) == 4, out
        for label, (release, peak, rise) in runs.items():
            if label.startswith('velocity="body"'):
                assert peak > 1.5 * release and rise > 1e-3, out
            else:
                assert peak == release and rise < 1e-6, out
    if name == "stability.py":
        # The default contact step is at least 2x inside the step where the fastest supported throw
        # (50 m/s) gains energy in a contact; the water is stable at 0.99 of its bound, not at 1.01.
        m = re.search(r"default dt 2.5e-4 s is ([\d.]+|inf)x inside", out)
        assert m and float(m.group(1)) >= 2.0, out
        # (stop 48) the free thin disk: Euler adds energy at the whole stability estimate and not at a quarter of it,
        # where its warning begins (STABLE_FRACTION); RK4 at most a few per cent up to the whole (full run: 2.9 %)
        rises = {}
        for integrator in ("euler", "rk4"):
            line = re.search(r"thin disk at 40 m/s, " + integrator + r" *: (.*)", out).group(1)
            rises[integrator] = {float(r): float(mx) for r, mx in re.findall(r"([\d.]+): median [-+\d.]+ %, max ([-+\d.]+) %", line)}
        assert rises["euler"][1.0] > 20.0 and rises["euler"][0.25] < 1.0, rises
        assert max(rises["rk4"].values()) < 5.0, rises
        growth = dict(re.findall(r"([\d.]+): ([\d.e+]+)", re.search(r"ripple growth.*", out).group(0)))
        assert float(growth["0.99"]) < 10 and float(growth["1.01"]) > 100, out
        # float32's smooth clipping is best near kappa 1e3-1e5 /m and loses to cancellation beyond
        # (> 1e-3 at 1e8 /m), where float64 is still within 1e-8 of exact clipping.
        err = {}
        for prec in ("float64", "float32"):
            m = re.search(prec + r": area error at kappa = 1e2, 1e4, 1e6, 1e8 /m: (.*?); smallest at kappa ([\d.e+]+)", out)
            err[prec] = [float(v) for v in m.group(1).split(", ")] + [float(m.group(2))]
        assert err["float32"][3] > 1e-3 and err["float64"][3] < 1e-8, out
        assert 1e3 <= err["float32"][4] <= 1e5, out
