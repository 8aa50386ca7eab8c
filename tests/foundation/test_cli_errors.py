"""Bad input gives one line ``millpath: error: FILE[:LINE]: message``, exit status 1,
no traceback and no partial output."""

import subprocess
import sys

from click.testing import CliRunner

from millpath.cli.main import cli


def run(args):
    return CliRunner().invoke(cli, args)


def test_missing_job_file_is_one_line_error(tmp_path):
    r = run(["run", str(tmp_path / "nope.toml"), "-o", str(tmp_path / "out")])
    assert r.exit_code == 1
    assert r.output.strip() == f"millpath: error: {tmp_path / 'nope.toml'}: no such job file"
    assert not (tmp_path / "out").exists()


def test_invalid_toml_names_file_and_line(tmp_path):
    p = tmp_path / "job.toml"
    p.write_text('units = "mm"\n\nstock = [1, 2\n')
    r = run(["run", str(p), "-o", str(tmp_path / "out")])
    assert r.exit_code == 1
    line = r.output.strip()
    assert line.startswith(f"millpath: error: {p}:3: invalid TOML")
    assert "\n" not in line and "Traceback" not in r.output


def test_nan_in_a_planned_path_is_an_error_and_writes_nothing(tmp_path, job_file):
    job_file.write_text(job_file.read_text() + "fail = true\n")
    out = tmp_path / "out"
    out.mkdir()
    (out / "program.ngc").write_text("old program\n")
    r = run(["run", str(job_file), "-o", str(out)])
    assert r.exit_code == 1
    assert "non-finite coordinate" in r.output and r.output.count("\n") == 1
    assert [f.name for f in out.iterdir()] == ["program.ngc"]
    assert (out / "program.ngc").read_text() == "old program\n"


def test_console_script_reports_errors_without_traceback(tmp_path):
    p = subprocess.run([sys.executable, "-m", "millpath.cli.main", "run",
                        str(tmp_path / "missing.toml")], capture_output=True, text=True)
    assert p.returncode == 1
    assert p.stderr.startswith("millpath: error: ") and "Traceback" not in p.stderr


def test_debug_flag_shows_the_traceback(tmp_path):
    p = subprocess.run([sys.executable, "-m", "millpath.cli.main", "--debug", "run",
                        str(tmp_path / "missing.toml")], capture_output=True, text=True)
    assert p.returncode != 0 and "Traceback" in p.stderr
