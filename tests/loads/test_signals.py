"""Time signals against their formulas; CSV and OpenFAST tables written here."""

from __future__ import annotations

import math
import struct

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.errors import (
    InputError,
    NonFiniteInput,
    TableNotUtf8,
    TableStartsLate,
    TorquesUnbalanced,
)
from pinwind.loads.openfast import read_channel
from pinwind.loads.signal_text import parse_signal, signal_from_spec
from pinwind.loads.signals import (
    Constant,
    Ramp,
    Sine,
    Step,
    Sum,
    read_csv,
)
from pinwind.model.gearbox import loads

T = np.linspace(0.0, 10.0, 1001)


def test_constant_ramp_step_and_sine_follow_their_formulas_at_sample_times():
    assert_allclose(Constant(3.5).values(T), 3.5, rtol=0)
    ramp = Ramp(start_value=1.0, end_value=5.0, start_time=2.0, end_time=6.0)
    expected = np.where(T < 2, 1.0, np.where(T > 6, 5.0, 1.0 + (T - 2.0)))
    assert_allclose(ramp.values(T), expected, rtol=1e-15, atol=1e-15)
    step = Step(time=3.0, before=-1.0, after=2.0)
    assert_allclose(step.values(T), np.where(T >= 3.0, 2.0, -1.0), rtol=0)
    sine = Sine(mean=200.0, amplitude=9.2, frequency=0.1, phase=0.3)
    expected = [200.0 + 9.2 * math.sin(2 * math.pi * 0.1 * t + 0.3) for t in T]
    assert_allclose(sine.values(T), expected, rtol=1e-15)
    total = ramp + sine + step
    assert isinstance(total, Sum) and len(total.terms) == 3
    assert_allclose(total.values(T), ramp.values(T) + sine.values(T) + step.values(T), rtol=1e-15)


def test_text_form_reads_back_every_signal_and_its_spec():
    text = "ramp(start_value=0, end_value=1e6, start_time=0, end_time=5) + sine(mean=0, " + (
        "amplitude=1e5, frequency=0.5)"
    )
    signal = parse_signal(text)
    again = parse_signal(signal.description)
    assert_allclose(again.values(T), signal.values(T), rtol=0)
    assert_allclose(signal_from_spec(signal.spec()).values(T), signal.values(T), rtol=0)
    assert parse_signal("1e6") == Constant(1e6)
    assert signal_from_spec([1.0, {"type": "step", "time": 1, "before": 0, "after": 1}])(2.0) == 2


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("sinus(mean=1)", 'unknown signal "sinus"; signals are: constant, ramp, step, sine'),
        ("sine(mean=1, amplitude=2)", "sine\\(\\) needs frequency"),
        ("sine(mean=1, amplitude=2, frequency=1, period=3)", 'no parameter "period"'),
        ("sine(1, 2, 3)", "give sine\\(\\) its parameters by name"),
        (
            'sine(**{"mean": 1, "amplitude": 2, "frequency": 1})',
            "give sine\\(\\) its parameters as key=value, not as \\*\\*",
        ),
        ("ramp(start_value=0, end_value=1, start_time=2, end_time=1)", "must be after"),
    ],
)
def test_malformed_signal_text_names_the_valid_choices(text, message):
    with pytest.raises(InputError, match=message):
        parse_signal(text, where="--torque carrier")


def test_csv_table_interpolates_linearly_between_rows(tmp_path):
    path = tmp_path / "torque.csv"
    path.write_text("time,torque\n0,0\n1,10\n3,-10\n")
    table = read_csv(path, "torque")
    assert_allclose(table.values(np.array([0.0, 0.5, 1.0, 2.0, 2.5, 3.0])),
                    [0.0, 5.0, 10.0, 0.0, -5.0, -10.0], rtol=1e-15)  # fmt: skip


@pytest.mark.parametrize(
    ("rows", "message"),
    [
        ("0,0\n2,1\n1,2\n", "torque.csv: row 4 goes back from the time of row 3"),
        ("0,0\n1,1\n1,2\n", "torque.csv: row 4 repeats the time of row 3"),
        ("0,0\n1,nan\n2,2\n", "torque.csv: row 3 has time 1.0 s, value nan"),
        ("0,0\n1,x\n", "torque.csv: row 3 .* does not have numbers"),
    ],
)
def test_bad_csv_rows_are_refused_naming_file_and_row(tmp_path, rows, message):
    path = tmp_path / "torque.csv"
    path.write_text("time,torque\n" + rows)
    with pytest.raises(InputError, match=message):
        read_csv(path)


def test_csv_with_a_utf8_byte_order_mark_keeps_its_first_row(tmp_path):
    # Excel's "CSV UTF-8" starts the file with EF BB BF: without a header, row 1 is data.
    path = tmp_path / "torque.csv"
    path.write_bytes(b"\xef\xbb\xbf0,5\n1,7\n")
    table = read_csv(path)
    assert_allclose(table.times, [0.0, 1.0], rtol=0, atol=0)
    assert_allclose(table.values(np.array([0.0, 0.5])), [5.0, 6.0], rtol=1e-15)


def test_csv_with_a_byte_order_mark_finds_its_first_header_name(tmp_path):
    path = tmp_path / "torque.csv"
    path.write_bytes(b"\xef\xbb\xbftime,torque\n0,5\n1,7\n")
    table = read_csv(path, "torque", time_column="time")
    assert_allclose(table.samples, [5.0, 7.0], rtol=0, atol=0)


def test_latin1_csv_is_refused_naming_file_and_byte(tmp_path):
    path = tmp_path / "torque.csv"
    path.write_bytes("time,torque µ\n0,5\n1,7\n".encode("latin-1"))
    # "time,torque " is 12 bytes: µ (0xb5) is byte 12.
    with pytest.raises(TableNotUtf8, match=r"torque.csv: byte 12 \(0xb5\) is not UTF-8") as err:
        read_csv(path)
    assert (err.value.position, err.value.byte) == (12, 0xB5)


def test_table_starting_after_the_run_is_warned_naming_file_and_times(tmp_path, pair_urdf):
    path = tmp_path / "torque.csv"
    path.write_text("time,torque\n0.2,3\n1,4\n")
    gb = loads(pair_urdf(), path="pair.urdf")
    with (
        pytest.warns(TorquesUnbalanced),
        pytest.warns(
            TableStartsLate,
            match=r"torque.csv starts at t = 0.2 s but the run starts at t = 0 s; its first "
            r"value 3 is held",
        ) as caught,
    ):
        pinwind.simulate(gb, duration=0.01, dt=1e-3, torques={"a": read_csv(path)})
    assert [w.message.start for w in caught if w.category is TableStartsLate] == [0.2]


def test_run_longer_than_its_table_is_refused_naming_file_and_last_row(tmp_path, pair_urdf):
    path = tmp_path / "torque.csv"
    path.write_text("# brake torque\ntime,torque\n0,1\n0.5,2\n")
    gb = loads(pair_urdf(), path="pair.urdf")
    with pytest.raises(InputError, match=r"torque.csv ends at row 4 \(t = 0.5 s\) but the run"):
        pinwind.simulate(gb, duration=1.0, dt=1e-3, torques={"a": read_csv(path)})


def test_signals_drive_torques_and_speed_drivers_in_the_run(tmp_path, pair_urdf):
    gb = loads(pair_urdf(), path="pair.urdf")
    speed = Sine(mean=100.0, amplitude=10.0, frequency=2.0)
    res = pinwind.simulate(gb, duration=0.5, dt=1e-3, speeds={"a": speed},
                           torques={"b": Step(time=0.2, before=0.0, after=3.0)})  # fmt: skip
    assert_allclose(res.joint("a").speed, speed.values(res.time), rtol=1e-12)
    assert_allclose(res.joint("b").torque, np.where(res.time >= 0.2, 3.0, 0.0), atol=1e-12)
    # The same run with Python callables (the slow path) gives the same answer.
    slow = pinwind.simulate(gb, duration=0.5, dt=1e-3, speeds={"a": lambda t: speed(t)},
                            torques={"b": lambda t: 3.0 if t >= 0.2 else 0.0})  # fmt: skip
    assert_allclose(slow.joint("a").torque, res.joint("a").torque, rtol=1e-9, atol=1e-9)


def _write_outb(path, names, units, data):
    """An OpenFAST binary output (FileFmtID_WithoutTime = 2, int16 channels)."""
    n_t, n_ch = data.shape
    scale = np.full(n_ch, 100.0, dtype=np.float32)
    offset = np.zeros(n_ch, dtype=np.float32)
    packed = np.round(data * scale + offset).astype(np.int16)
    description = b"written by pinwind's tests"
    with open(path, "wb") as f:
        f.write(struct.pack("<h", 2))
        f.write(struct.pack("<ii", n_ch, n_t))
        f.write(struct.pack("<dd", 0.0, 0.05))  # first time, increment [s]
        f.write(scale.tobytes() + offset.tobytes())
        f.write(struct.pack("<i", len(description)) + description)
        for name in ["Time", *names]:
            f.write(name.ljust(10).encode())
        for unit in ["(s)", *units]:
            f.write(unit.ljust(10).encode())
        f.write(packed.tobytes())


def test_openfast_binary_channel_is_read_with_its_unit_scale(tmp_path):
    t = np.arange(6) * 0.05
    data = np.column_stack([10.0 + t, 300.0 * np.ones(6) + 20 * t])  # RotSpeed rpm, RotTorq kN·m
    path = tmp_path / "run.outb"
    _write_outb(path, ["RotSpeed", "RotTorq"], ["(rpm)", "(kN-m)"], data)
    torque = read_channel(path, "RotTorq", scale=1000.0)
    assert_allclose(torque.values(t), 1000.0 * data[:, 1], rtol=1e-12)
    assert_allclose(torque(0.025), 1000.0 * 300.5, rtol=1e-12)  # linear between samples
    with pytest.raises(InputError, match='no channel "GenTq"; channels are: RotSpeed, RotTorq'):
        read_channel(path, "GenTq")


def test_openfast_text_channel_is_read_like_openfast_writes_it(tmp_path):
    header = ["", "Predictions were generated by OpenFAST", "", "", "test run", "",
              "Time\tGenTq\tGenSpeed", "(s)\t(kN-m)\t(rpm)"]  # fmt: skip
    rows = ["0.0\t1.0\t1200", "0.1\t2.0\t1210", "0.2\t4.0\t1220"]
    path = tmp_path / "run.out"
    path.write_text("\n".join(header + rows) + "\n")
    signal = parse_signal(f'openfast(file="{path}", channel="GenTq", scale=1000)')
    assert_allclose(signal.values(np.array([0.0, 0.05, 0.15])), [1000, 1500, 3000], rtol=1e-12)


def test_non_finite_constant_is_refused():
    with pytest.raises(NonFiniteInput):
        signal_from_spec({"type": "sine", "mean": float("nan"), "amplitude": 1, "frequency": 1})


def test_openfast_text_output_with_a_header_and_no_rows_is_refused_naming_its_channels(tmp_path):
    header = ["", "Predictions were generated by OpenFAST", "", "", "test run", "",
              "Time\tGenTq\tGenSpeed", "(s)\t(kN-m)\t(rpm)"]  # fmt: skip
    path = tmp_path / "run.out"
    path.write_text("\n".join(header) + "\n")
    with pytest.raises(InputError, match=r"run.out: .* \(channels Time, GenTq, GenSpeed\) but no"):
        parse_signal(f'openfast(file="{path}", channel="GenTq", scale=1000)')
    path.write_text("\n".join([*header, "0.0\t1.0\t1200"]) + "\n")  # one row: not a table
    with pytest.raises(InputError, match="a table needs at least two rows"):
        parse_signal(f'openfast(file="{path}", channel="GenTq", scale=1000)')


@pytest.mark.parametrize("lines", [0, 2, 6, 7], ids=["empty", "title", "before-names", "no-units"])
def test_openfast_text_output_cut_inside_its_header_is_one_line_naming_the_file(tmp_path, lines):
    """A header cut before its channel names or its units raised numpy's "cannot reshape"."""
    header = ["", "Predictions were generated by OpenFAST", "", "", "test run", "",
              "Time\tGenTq\tGenSpeed", "(s)\t(kN-m)\t(rpm)"]  # fmt: skip
    path = tmp_path / "run.out"
    path.write_text("\n".join(header[:lines]))
    with pytest.raises(InputError, match=r"run.out: the file ends inside its OpenFAST header") as e:
        parse_signal(f'openfast(file="{path}", channel="GenTq", scale=1000)')
    assert "\n" not in str(e.value)
