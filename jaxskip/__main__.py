"""``python -m jaxskip`` runs the command line."""

from .cli import main

raise SystemExit(main())
