"""Whole-folder atomic output: runs killed at random moments and two
concurrent runs into one folder never leave a mixed or half-written output folder."""

import json
import os
import random
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from millpath.errors import MillpathError
from millpath.io.atomic import output_lock, staged_dir

EXAMPLE = Path(__file__).resolve().parents[2] / "millpath" / "examples" / "features-holes-slot"
FILES = {"program.ngc", "tools.tbl", "report.json", "preview.png", "stock.png", "view.html",
         "deviation.png"}


def _jobs(tmp_path):
    """Two jobs on the same part whose outputs differ (name, clearance)."""
    for f in EXAMPLE.iterdir():
        shutil.copy(f, tmp_path / f.name)
    text = (EXAMPLE / "job.toml").read_text()
    a = tmp_path / "a.toml"
    a.write_text(text.replace('name = "features-holes-slot"', 'name = "run-a"'))
    b = tmp_path / "b.toml"
    b.write_text(text.replace('name = "features-holes-slot"', 'name = "run-b"')
                 .replace("allowance = 0.2", "allowance = 0.2\nclearance = 9"))
    return a, b


def _cmd(job, out):
    return [sys.executable, "-m", "millpath.cli.main", "run", str(job), "-o", str(out),
            "--quiet"]


def _check_whole(out: Path) -> str | None:
    """The name of the run whose complete output ``out`` holds (None: no folder)."""
    if not out.exists():
        return None
    names = {f.name for f in out.iterdir() if not f.name.startswith(".")}
    assert names == FILES, names
    rep = json.loads((out / "report.json").read_text())
    prog = (out / "program.ngc").read_text()
    assert prog.startswith(f"({rep['name']}:"), "program and report of different runs"
    assert rep["lines"] == prog.count("\n")
    assert prog.rstrip().endswith("M2")
    return rep["name"]


@pytest.mark.slow
def test_sigkill_at_random_moments_never_leaves_a_mixed_folder(tmp_path):
    a, b = _jobs(tmp_path)
    out = tmp_path / "out"
    t0 = time.perf_counter()
    assert subprocess.run(_cmd(a, out), capture_output=True).returncode == 0
    full = time.perf_counter() - t0
    assert _check_whole(out) == "run-a"
    rng = random.Random(1614)
    for i in range(8):
        job = b if i % 2 == 0 else a
        p = subprocess.Popen(_cmd(job, out), stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL)
        try:
            p.wait(timeout=rng.uniform(0.3, 1.2) * full)
        except subprocess.TimeoutExpired:
            p.send_signal(signal.SIGKILL)
            p.wait()
        # the folder holds one run's whole output, or (killed between the two renames
        # of a system without renameat2) nothing, with the backup restored next run
        _check_whole(out)
    assert subprocess.run(_cmd(a, out), capture_output=True).returncode == 0
    assert _check_whole(out) == "run-a"
    left = [p.name for p in tmp_path.iterdir() if p.name.startswith(".out.")]
    assert left == [".out.lock"], left


#: a run that stops at the folder swap and says so: at the exchange (renameat2), or
#: without renameat2 between moving the old output away and moving the new one in
_PAUSE = {
    "exchange": "atomic._exchange = pause\n",
    "between-renames": ("atomic._exchange = lambda a, b: False\nreal = os.rename\n"
                        "def rename(a, b):\n    real(a, b)\n"
                        "    if '.backup-' in str(b):\n        pause()\n"
                        "os.rename = rename\n"),
}


@pytest.mark.slow
@pytest.mark.parametrize("where", sorted(_PAUSE))
def test_sigkill_during_the_folder_swap(tmp_path, where):
    """A kill that lands in the switch itself (none of the random kills above did): the
    previous output stays whole (or, between the two renames, whole in its backup), and
    the next run restores it or replaces it, leaving no staging or backup folder."""
    a, b = _jobs(tmp_path)
    out = tmp_path / "out"
    assert subprocess.run(_cmd(a, out), capture_output=True).returncode == 0
    code = ("import os, sys, time\nimport millpath.io.atomic as atomic\n"
            "def pause(*args):\n    print('swap', flush=True)\n    time.sleep(300)\n"
            + _PAUSE[where] + "from millpath.cli.main import main\n"
            f"sys.argv = {['millpath', *_cmd(b, out)[3:]]!r}\nmain()\n")
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    try:
        assert p.stdout.readline().strip() == "swap"
    finally:
        p.kill()
        p.wait()
    backups = list(tmp_path.glob(".out.backup-*"))
    if where == "exchange":
        assert _check_whole(out) == "run-a" and not backups
    else:
        assert not out.exists() and len(backups) == 1 and _check_whole(backups[0]) == "run-a"
    assert list(tmp_path.glob(".out.staging-*"))          # the new output, never switched
    assert subprocess.run(_cmd(b, out), capture_output=True).returncode == 0
    assert _check_whole(out) == "run-b"
    left = [p.name for p in tmp_path.iterdir() if p.name.startswith(".out.")]
    assert left == [".out.lock"], left


@pytest.mark.slow
def test_two_runs_into_one_folder_do_not_mix(tmp_path):
    a, b = _jobs(tmp_path)
    out = tmp_path / "out"
    pa = subprocess.Popen(_cmd(a, out), stderr=subprocess.PIPE, text=True)
    time.sleep(0.1)
    pb = subprocess.Popen(_cmd(b, out), stderr=subprocess.PIPE, text=True)
    ea, eb = pa.communicate(timeout=300)[1], pb.communicate(timeout=300)[1]
    codes = sorted([pa.returncode, pb.returncode])
    assert codes in ([0, 0], [0, 1])
    for code, err in ((pa.returncode, ea), (pb.returncode, eb)):
        if code == 1:
            lines = err.strip().splitlines()
            assert len(lines) == 1 and "being written by another millpath run" in lines[0]
            assert str(out) in lines[0]
    assert _check_whole(out) in ("run-a", "run-b")


def test_second_lock_in_another_process_fails_with_a_clear_message(tmp_path):
    out = tmp_path / "out"
    code = ("import sys, time; from millpath.io.atomic import output_lock\n"
            f"with output_lock({str(out)!r}):\n    print('held', flush=True); time.sleep(30)")
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    try:
        assert p.stdout.readline().strip() == "held"
        with pytest.raises(MillpathError, match=rf"{out}: output folder is being written by "
                                                rf"another millpath run \(process {p.pid}\)"):
            with output_lock(out):
                pass
    finally:
        p.kill()
        p.wait()
    with output_lock(out):           # the kernel dropped the dead run's lock
        pass


def test_stale_staging_removed_and_backup_restored(tmp_path):
    out = tmp_path / "out"
    (tmp_path / ".out.staging-dead1").mkdir()
    (tmp_path / ".out.staging-dead1" / "program.ngc").write_text("half")
    backup = tmp_path / ".out.backup-dead2"
    backup.mkdir()
    (backup / "report.json").write_text("{}")
    with output_lock(out):
        pass
    assert not (tmp_path / ".out.staging-dead1").exists()
    assert (out / "report.json").read_text() == "{}" and not backup.exists()


def test_folder_with_foreign_files_is_not_replaced(tmp_path):
    out = tmp_path / "home"
    out.mkdir()
    (out / "thesis.tex").write_text("precious")
    with pytest.raises(MillpathError, match="holds files millpath did not write"):
        with staged_dir(out) as tmp:
            (tmp / "program.ngc").write_text("M2\n")
    assert (out / "thesis.tex").read_text() == "precious"


def test_writable_folder_in_read_only_parent(tmp_path, monkeypatch):
    """Lock and staging move inside the folder when its parent cannot be written
    (simulated: the tests may run as root, whom permissions do not stop)."""
    import millpath.io.atomic as atomic
    monkeypatch.setattr(atomic, "_parent_writable", lambda final: False)
    out = tmp_path / "out"
    out.mkdir()
    (out / "old.png").write_bytes(b"old")
    with staged_dir(out) as tmp:
        assert tmp.parent == out
        (tmp / "program.ngc").write_text("M2\n")
    assert sorted(f.name for f in out.iterdir()) == [".millpath-output", ".millpath.lock",
                                                      "program.ngc"]
    assert list(tmp_path.iterdir()) == [out]


def test_written_files_have_the_users_umask_permissions(tmp_path):
    """Outputs are created as ``open()`` would create them (0666 less the umask), not with
    the temp file's private 0600: a shop's other users (or the machine's) can read them."""
    import os
    import stat

    from millpath.io.atomic import staged_dir, write_text
    old = os.umask(0o022)
    try:
        write_text(tmp_path / "a.ngc", "M2\n")
        assert stat.S_IMODE((tmp_path / "a.ngc").stat().st_mode) == 0o644
        with staged_dir(tmp_path / "out") as tmp:
            write_text(tmp / "program.ngc", "M2\n")
        assert stat.S_IMODE((tmp_path / "out").stat().st_mode) == 0o755
        assert stat.S_IMODE((tmp_path / "out" / "program.ngc").stat().st_mode) == 0o644
    finally:
        os.umask(old)
