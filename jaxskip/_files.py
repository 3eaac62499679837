"""Errors of writing a file that name the file.

An error raised by ``write()`` itself, not by ``open()`` — a full disk (``ENOSPC``), a quota (``EDQUOT``),
an I/O error — carries no file name: ``[Errno 28] No space left on device`` leaves a user of
``jaxskip throw --plot a.png --trajectory t.csv --json`` to guess which of three outputs failed.
:func:`writing` puts the name in.

Example::

    with writing(path):
        fig.savefig(path)
"""

from __future__ import annotations

import contextlib
import errno
import os

from ._checks import ParameterError

#: What :func:`writing` calls standard output.
STDOUT = "standard output"


@contextlib.contextmanager
def writing(what):
    """Re-raise an :class:`OSError` without a file name, raised inside the block, as one that names ``what``
    (a path, or :data:`STDOUT`): ``[Errno 28] cannot write 'a.png': No space left on device``.

    Left as they are: errors that name a file already (``open()``'s), and a closed pipe (``EPIPE``: the
    reader went away, which the CLI reports by its exit status alone)."""
    try:
        yield
    except OSError as exc:
        if exc.filename is not None or exc.errno in (None, errno.EPIPE):
            raise
        if what == STDOUT:
            name = what
        elif isinstance(what, (str, bytes, os.PathLike)):
            name = repr(os.fsdecode(what))
        else:  # a file object (savefig takes one)
            name = repr(getattr(what, "name", what))
        raise OSError(exc.errno, f"cannot write {name}: {exc.strerror or exc}") from exc


def check_file_path(name: str, path) -> None:
    """Refuse, before anything is drawn or computed, an output path (``str`` or ``os.PathLike``) that names a
    folder or lies in a folder that does not exist: the error came from ``savefig`` or ``Image.save`` after
    every frame had been drawn. ``None`` and file objects pass. Raises :class:`ParameterError` naming ``name``."""
    if path is None or not isinstance(path, (str, os.PathLike)):
        return
    text = os.fsdecode(os.fspath(path))
    folder = os.path.dirname(text) or "."
    if not os.path.isdir(folder):
        raise ParameterError(f"{name}: the folder {folder!r} of {text!r} does not exist")
    if os.path.isdir(text):
        raise ParameterError(f"{name} must name a file, got the folder {text!r}")


def check_picture_path(name: str, path) -> None:
    """Refuse, before anything is drawn, a picture path (``str`` or ``os.PathLike``) without a suffix that
    matplotlib writes: ``"h2"`` was saved as ``h2.png``, a file the caller never named, and ``"h2.tx"``
    failed after the figure was drawn. ``None`` and file objects (which ``savefig`` takes) pass."""
    if path is None:
        return
    if not isinstance(path, (str, os.PathLike)):
        if not callable(getattr(path, "write", None)):   # (5 met a raw AttributeError from savefig)
            raise ParameterError(f"{name} must be a file path (.png, .pdf or .svg) or a binary file object, got "
                                 f"{type(path).__name__}")
        return
    from matplotlib.backend_bases import FigureCanvasBase

    formats = FigureCanvasBase.get_supported_filetypes()
    text = os.fsdecode(os.fspath(path))
    ext = os.path.splitext(os.path.basename(text))[1].lower().lstrip(".")
    if ext not in formats:
        raise ParameterError(f"{name} must end in a picture format matplotlib writes ({', '.join(sorted(formats))}"
                             f"; the CLI takes .png, .pdf and .svg), got {text!r}"
                             + (" (no suffix: matplotlib would write another file name, with .png)" if not ext else ""))
    check_file_path(name, path)
