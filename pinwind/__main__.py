"""``python -m pinwind`` runs the command-line interface."""

from pinwind.cli import main

main()
