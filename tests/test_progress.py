"""The progress line: rewritten in place on a terminal, one line per update (throttled) in a log file."""

import io
import re

import jaxskip._progress as progress_module
from jaxskip import Throw, simulate_batch
from jaxskip._progress import ProgressLine


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_a_terminal_gets_every_update_rewritten_in_place():
    out = _Terminal()
    line = ProgressLine(out)
    for i in range(3):
        line.update(f"  {i + 1}/3 done")
    line.close()
    assert out.getvalue() == "\r  1/3 done\r  2/3 done\r  3/3 done\n"


def test_a_log_file_gets_whole_lines_at_most_every_interval_and_the_last(monkeypatch):
    """Off a terminal, ``\\r`` rewrites piled up as one ever longer line (session 25's logs)."""
    clock = iter([0.0, 1.0, 2.0, 6.0, 7.0])
    monkeypatch.setattr(progress_module.time, "monotonic", lambda: next(clock))
    out = io.StringIO()
    line = ProgressLine(out)
    for i in range(5):
        line.update(f"  {i + 1}/5 done")
    line.close()
    # 0 s: written; 1, 2 s: held back; 6 s: written (5 s since 0 s); 7 s: held, written by close
    assert out.getvalue() == "  1/5 done\n  4/5 done\n  5/5 done\n"
    assert "\r" not in out.getvalue()


def test_nothing_shown_nothing_closed():
    for out in (io.StringIO(), _Terminal()):
        ProgressLine(out).close()
        assert out.getvalue() == ""


def test_simulate_batch_progress_into_a_file_has_no_carriage_returns(capsys):
    simulate_batch(Throw.from_degrees(speed=[5.0, 6.0]), progress=True)
    err = capsys.readouterr().err
    assert "\r" not in err
    assert err.endswith("\n") and err.splitlines()[-1].startswith("  2/2 throws done (")


def test_simulate_progress_counts_the_steps_in_play(capsys):
    """The last progress line of a throw gives its steps in play, ThrowResult.steps (the default throw:
    1147), not the chunks run (it said 2000: two chunks of 1000)."""
    from jaxskip import simulate

    result = simulate(progress=True)
    last = capsys.readouterr().err.splitlines()[-1]
    assert result.steps < 2000
    assert last.endswith(f" s in {result.steps} steps"), last


def test_simulate_batch_progress_says_when_it_compiles_and_how_long_it_has_run(capsys):
    """(stop 46, a review) nothing was printed during the pool's compile (simulate says 'compiling'), and the line
    gave lane-steps with no time."""
    import dataclasses

    from jaxskip import SimConfig

    config = dataclasses.replace(SimConfig(), max_contacts=63)   # (a pool program no other test compiles)
    simulate_batch(Throw.from_degrees(speed=[5.0, 6.0]), config=config, progress=True)
    err = capsys.readouterr().err
    assert err.startswith("  compiling the pool's program (") and re.search(r"2/2 throws done \(\d+ lane-steps, \d+ s\)\n$", err)
    simulate_batch(Throw.from_degrees(speed=[5.0, 7.0]), config=config, progress=True)
    assert "compiling" not in capsys.readouterr().err


def test_simulate_batch_progress_names_the_compile_of_its_last_shorter_chunk(capsys):
    """(stop 46, a review of the session) a chunk that does not divide max_steps runs a throw's last steps in a second
    program, compiled when first needed: the progress says so too."""
    import dataclasses

    from jaxskip import SimConfig

    config = dataclasses.replace(SimConfig(), max_contacts=62, max_steps=1001)   # (programs no other test compiles)
    r = simulate_batch(Throw.from_degrees(speed=[9.0, 9.5], attack=1.0), config=config, chunk=250, progress=True)
    err = capsys.readouterr().err
    assert "step_limit" in r.outcome_names.tolist()
    assert "compiling the pool's last, 1-step chunk (max_steps 1001 is not a multiple of the chunk, 250)" in err, err
