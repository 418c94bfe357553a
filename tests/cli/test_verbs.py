"""The table of verbs that lets a command import only its verb's module (``pinwind/cli``)."""

from __future__ import annotations

import typer.main

from pinwind.cli import VERB_MODULES, app


def test_every_verb_is_in_the_table_with_the_module_that_registers_it():
    group = typer.main.get_command(app)
    assert isinstance(group, typer.main.TyperGroup)
    assert set(group.commands) == set(VERB_MODULES)
    for verb, command in group.commands.items():
        # ``build`` and ``sweep`` are groups whose commands one verb module registers.
        commands = list(getattr(command, "commands", {}).values()) or [command]
        for each in commands:
            assert each.callback is not None, verb
            assert each.callback.__module__ == f"pinwind.cli.{VERB_MODULES[verb]}", (verb, each)
