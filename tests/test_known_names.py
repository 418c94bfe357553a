"""The one check of the names a file may use (``pinwind.known_names``)."""

from __future__ import annotations

import pytest

from pinwind.known_names import check_keys, nearest, toml_keys, unknown_message, unknown_name

KEYS = ("model", "duration", "dt", "torque", "speed", "initial_speed")


@pytest.mark.parametrize(
    ("name", "meant"),
    [("durtion", "duration"), ("Duration", "duration"), ("initial_sped", "initial_speed"),
     ("colour", None)],
)  # fmt: skip
def test_nearest_is_the_known_name_a_slip_of_the_keyboard_meant(name, meant):
    assert nearest(name, KEYS) == meant


def test_the_first_unknown_name_is_found_in_the_order_given():
    assert unknown_name(["dt", "durtion", "colour"], KEYS) == "durtion"
    assert unknown_name(["dt", "model"], KEYS) is None


def test_the_message_names_the_name_the_guess_and_every_known_name():
    message = unknown_message("durtion", KEYS, "key", " of the scenario")
    assert message == (
        'unknown key "durtion"; did you mean "duration"? keys of the scenario are: model, '
        "duration, dt, torque, speed, initial_speed"
    )
    assert "did you mean" not in unknown_message("colour", KEYS)


def test_a_toml_tables_unknown_key_is_refused_by_the_readers_error_at_its_path():
    def fail(key: tuple[str, ...], message: str) -> Exception:
        return KeyError(key, message)

    table = toml_keys({"initial-speed": 1.0, "durtion": 2.0})
    assert list(table) == ["initial_speed", "durtion"]
    with pytest.raises(KeyError) as caught:
        check_keys(("fatigue",), table, KEYS, fail)
    assert caught.value.args == (("fatigue", "durtion"), unknown_message("durtion", KEYS))
    check_keys(("fatigue",), {"dt": 1e-3}, KEYS, fail)  # nothing unknown: no error
