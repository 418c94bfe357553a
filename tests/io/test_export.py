"""pinwind export: Parquet and CSV tables of a log, checked against the read-back Result."""

from __future__ import annotations

import csv

import numpy as np
import pyarrow.parquet as pq
import pytest

import pinwind
from pinwind.errors import ExportFailed, InputError, LogError, LogExists
from pinwind.io.export import export_log
from tests.io.test_cli_log import run


def expected_columns(res: pinwind.Result) -> dict[str, np.ndarray]:
    """Every column the export should have, built from the Result's accessors."""
    out = {"time_s": res.time}
    for name in res.joint_names:
        j = res.joint(name)
        out[f"joint/{name}/angle_rad"] = j.angle
        out[f"joint/{name}/speed_rad_s"] = j.speed
        out[f"joint/{name}/acceleration_rad_s2"] = j.acceleration
        out[f"joint/{name}/torque_N_m"] = j.torque
    for name in res.mesh_names:
        m = res.mesh(name)
        out[f"mesh/{name}/normal_N"] = m.normal
        out[f"mesh/{name}/tangential_N"] = m.tangential
        out[f"mesh/{name}/radial_N"] = m.radial
        out[f"mesh/{name}/axial_N"] = m.axial
        out[f"mesh/{name}/flank"] = m.flank
        out[f"mesh/{name}/normal_front_N"] = m.normal_front
        out[f"mesh/{name}/normal_back_N"] = m.normal_back
        out[f"mesh/{name}/transmission_error_m"] = m.transmission_error
        # the compliant mesh's series (0 or the rigid contact state for rigid meshes)
        out[f"mesh/{name}/deflection_m"] = m.deflection
        out[f"mesh/{name}/contact_position_m"] = m.contact_position
        out[f"mesh/{name}/pairs"] = m.pairs
        out[f"mesh/{name}/single_tooth_force_N"] = m.single_tooth_force
        out[f"mesh/{name}/face_load_factor"] = m.face_load_factor
        out[f"mesh/{name}/load_centre_m"] = m.load_centre
        out[f"mesh/{name}/peak_line_load_N_m"] = m.peak_line_load
        out[f"mesh/{name}/mean_line_load_N_m"] = m.mean_line_load
        # flank friction's series (compliant meshes; 0 for rigid ones)
        out[f"mesh/{name}/sliding_velocity_m_s"] = m.sliding_velocity
        out[f"mesh/{name}/friction_force_N"] = m.friction_force
        out[f"mesh/{name}/friction_power_W"] = m.friction_power
        for k, axis in enumerate("xyz"):
            out[f"mesh/{name}/force_on_b_{axis}_N"] = m.force_on_b[:, k]
            out[f"mesh/{name}/pitch_point_{axis}_m"] = m.pitch_point[:, k]
    for name in res.bearing_names:
        b = res.bearing(name)
        for k, axis in enumerate("xyz"):
            out[f"bearing/{name}/force_{axis}_N"] = b.force[:, k]
            out[f"bearing/{name}/moment_{axis}_N_m"] = b.moment[:, k]
            out[f"bearing/{name}/force_local_{axis}_N"] = b.force_local[:, k]
            out[f"bearing/{name}/moment_local_{axis}_N_m"] = b.moment_local[:, k]
        out[f"bearing/{name}/radial_N"] = b.radial
        out[f"bearing/{name}/axial_N"] = b.axial
        out[f"bearing/{name}/tilting_N_m"] = b.tilting
        out[f"bearing/{name}/torque_N_m"] = b.torque
        out[f"bearing/{name}/friction_moment_N_m"] = b.friction_moment
        out[f"bearing/{name}/friction_power_W"] = b.friction_power
        for k, axis in enumerate("xyz"):  # a compliant bearing's series (0 for ideal ones)
            out[f"bearing/{name}/displacement_{axis}_m"] = b.displacement[:, k]
            out[f"bearing/{name}/elastic_force_{axis}_N"] = b.elastic_force[:, k]
    for name in res.body_names:
        # a row per sample: the poses at the samples that have one, NaN at the others
        body = res.body(name)
        rows = np.searchsorted(res.time, body.time)
        for k, axis in enumerate("xyz"):
            out[f"body/{name}/position_{axis}_m"] = np.full(len(res), np.nan)
            out[f"body/{name}/position_{axis}_m"][rows] = body.position[:, k]
        for k, axis in enumerate("xyzw"):
            out[f"body/{name}/quaternion_{axis}"] = np.full(len(res), np.nan)
            out[f"body/{name}/quaternion_{axis}"][rows] = body.quaternion[:, k]
    for name in res.slice_names:  # a sliced mesh's slices (none in an unsliced run)
        out[f"slice/{name}/line_load_N_m"] = res.element("slice", name).line_load
    out["run/constraint_residual_m_s_or_rad_s"] = res.constraint_residual
    for term, values in res.energy.items():
        out[f"energy/{term}_J"] = values
    return out


def significant_digits(text: str) -> int:
    mantissa = text.lower().split("e")[0].lstrip("+-").replace(".", "").lstrip("0")
    return len(mantissa.rstrip("0")) if mantissa.isdigit() else 0


def bits(values) -> np.ndarray:
    return np.asarray(values, dtype=np.float64).view(np.uint64)


def test_parquet_export_round_trips_every_value_to_the_bit(logged_run, tmp_path):
    out = tmp_path / "run.parquet"
    rows, ncols = export_log(logged_run.path, out, block=64)
    table = pq.read_table(out)
    expected = expected_columns(pinwind.read_log(logged_run.path))
    assert table.column_names[0] == "time_s"
    assert set(table.column_names) == set(expected) and ncols == len(expected)
    assert rows == table.num_rows == len(expected["time_s"])
    for name, values in expected.items():
        np.testing.assert_array_equal(
            bits(table.column(name).to_numpy()), bits(values), err_msg=name
        )


def test_csv_export_round_trips_every_value_to_17_significant_digits(logged_run, tmp_path):
    out = tmp_path / "run.csv"
    export_log(logged_run.path, out, block=100)
    with open(out, newline="", encoding="utf-8") as f:
        reader = csv.reader(f)
        header = next(reader)
        text = list(reader)
    expected = expected_columns(pinwind.read_log(logged_run.path))
    assert set(header) == set(expected)
    for i, name in enumerate(header):
        column = [row[i] for row in text]
        assert max(significant_digits(v) for v in column) <= 17, name
        # 17 significant digits identify a float64 exactly
        np.testing.assert_array_equal(bits([float(v) for v in column]), bits(expected[name]))


def test_export_of_a_window_and_channels_has_only_those_columns_and_rows(logged_run, tmp_path):
    out = tmp_path / "meshes.parquet"
    export_log(logged_run.path, out, start=0.05, stop=0.2, channels=["/meshes/normal", "/joints"])
    table = pq.read_table(out)
    res = pinwind.read_log(logged_run.path, start=0.05, stop=0.2)
    names = ["time_s"]
    names += [f"joint/{j}/{q}" for j in res.joint_names for q in ("angle_rad", "speed_rad_s")]
    names += [f"joint/{j}/torque_N_m" for j in res.joint_names]
    names += [f"mesh/{m}/normal_N" for m in res.mesh_names]
    assert sorted(table.column_names) == sorted(names)
    assert table.num_rows == 151
    np.testing.assert_array_equal(
        table.column("mesh/sun_planet1/normal_N").to_numpy(), res.mesh("sun_planet1").normal
    )


def test_export_never_overwrites_a_table_without_force_and_needs_a_known_format(
    logged_run, tmp_path
):
    out = tmp_path / "keep.csv"
    out.write_text("precious")
    with pytest.raises(LogExists):
        export_log(logged_run.path, out)
    assert out.read_text() == "precious"
    with pytest.raises(InputError, match='export format "xlsx" is not one of parquet, csv'):
        export_log(logged_run.path, tmp_path / "run.xlsx")


def test_cli_export_writes_the_window_and_channels_asked_for(logged_run, tmp_path):
    out = tmp_path / "bearings.csv"
    result = run(
        "export",
        str(logged_run.path),
        "--format",
        "csv",
        "--from",
        "0.1",
        "--to",
        "0.12",
        "--channels",
        "/bearings/force,/run/energy",
        "-o",
        str(out),
    )
    assert result.returncode == 0, result.stderr
    header = out.read_text(encoding="utf-8").splitlines()[0].split(",")
    assert header[0] == "time_s" and "bearing/carrier/force_z_N" in header
    assert "energy/kinetic_J" in header and not any(h.startswith("mesh/") for h in header)
    assert f"wrote {out} (21 rows × {len(header)} columns)" in result.stdout.replace("\n", "")


@pytest.mark.parametrize("fmt", ["csv", "parquet"])
@pytest.mark.parametrize(
    ("where", "cause"),
    [("missing/run", "No such file or directory"), ("a_file/run", "Not a directory")],
)
def test_export_to_a_path_that_cannot_be_written_names_it_and_leaves_nothing(
    logged_run, tmp_path, fmt, where, cause
):
    (tmp_path / "a_file").write_text("not a folder")
    out = tmp_path / f"{where}.{fmt}"
    with pytest.raises(ExportFailed, match=f"cannot write the table \\({cause}\\)") as err:
        export_log(logged_run.path, out)
    assert err.value.path == str(out)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a_file"]


def test_failed_export_leaves_no_file_and_the_retry_writes_the_table(logged_run, tmp_path):
    out = tmp_path / "run.csv"
    with pytest.raises(LogError):
        export_log(tmp_path / "no_such_log.mcap", out)
    assert list(tmp_path.iterdir()) == []
    rows, _ = export_log(logged_run.path, out)
    assert rows == len(logged_run.result)


def test_cli_export_to_a_missing_folder_exits_2_with_one_line(logged_run, tmp_path):
    out = tmp_path / "missing" / "run.csv"
    result = run("export", str(logged_run.path), "-o", str(out))
    assert result.returncode == 2, result.stdout
    assert f"{out}: cannot write the table (No such file or directory)" in result.stderr
    assert result.stderr.count("\n") == 1, result.stderr
