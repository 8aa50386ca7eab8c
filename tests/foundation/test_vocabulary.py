"""One vocabulary: every renamed key's old name means its new name in every operation
type: accepted with a one-line deprecation warning naming the new key where the type
takes the new key (the same validated value), refused naming the new key where it does
not; giving both names is an error naming both."""

from __future__ import annotations

import warnings

import pytest

from millpath.errors import JobError, JobErrors, MillpathWarning
from millpath.job.jobfile import job_from_dict
from millpath.job.vocabulary import RENAMED
from millpath.plan.registry import STRATEGIES, strategy

#: the smallest valid operation of each renamed type (without the renamed key)
BASE = {
    "die-cavity": {"tool": 1, "points": [[0, 0], [40, 0], [40, 30], [0, 30]], "depth": 5.0,
                   "stepdown": 2.5, "tolerance": 0.01, "feed": 600.0},
    "features": {"step": "part.stp"},
    "grid-pocket": {"tool": 1, "polygon": [[0, 0], [40, 0], [40, 30], [0, 30]],
                    "bottom": {"bezier": [[-5, -5], [-5, -5]]}, "feed": 600.0,
                    "spindle": 8000.0},
    "pocket": {"tool": 1, "polygon": [[0, 0], [40, 0], [40, 30], [0, 30]], "depth": 5.0,
               "stepdown": 2.5, "feed": 600.0},
    "surface-rough": {"tool": 1, "surface": "part.stl"},
}
#: a value each renamed key accepts
VALUE = {"stepdown": 1.25, "stepover": 2.5, "allowance": 0.3}


def _job(op: dict) -> dict:
    return {"units": "mm", "stock": {"box": [0, 0, -10, 40, 30, 0]},
            "tools": [{"number": 1, "type": "flat", "diameter": 6.0}], "operations": [op]}


def _cases():
    """(type, old, new) of each type in BASE that takes the new key."""
    for op_type in sorted(BASE):
        params = strategy(op_type).PARAMS
        for old, new in RENAMED.items():
            if new in params and old not in params:
                yield op_type, old, new


def test_renamed_keys_are_new_names_of_existing_keys():
    for old, new in RENAMED.items():
        types = [t for t in STRATEGIES if new in strategy(t).PARAMS]
        assert types, (old, new)
        for op_type in types:
            assert old not in strategy(op_type).PARAMS or (op_type, old) == ("features",
                                                                             "step")


def _outcome(op: dict, tmp_path) -> tuple[list[str], list[str], dict | None]:
    """(error messages, warnings, validated operation or None) of a job of ``op``."""
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        try:
            job = job_from_dict(_job(op), tmp_path / "job.toml")
        except JobErrors as e:
            return [x.message for x in e.errors], [str(w.message) for w in got], None
    return [], [str(w.message) for w in got], job.operations[0][1]


#: every (operation type, old name, new name) where the old name is not a key of the
#: operation type's own (``step`` is one in features)
RENAMED_IN = [(t, old, new) for t in sorted(STRATEGIES) for old, new in sorted(RENAMED.items())
              if old not in strategy(t).PARAMS]


@pytest.mark.parametrize("op_type,old,new", RENAMED_IN)
def test_an_old_name_is_its_new_name_in_every_operation_type(op_type, old, new, tmp_path):
    params = strategy(op_type).PARAMS
    value = VALUE[new]
    errs_new, warned_new, got_new = _outcome({"type": op_type, new: value}, tmp_path)
    errs_old, warned_old, got_old = _outcome({"type": op_type, old: value}, tmp_path)
    assert not warned_new
    if new in params:
        assert errs_old == errs_new and got_old == got_new
        assert warned_old == [f"{tmp_path / 'job.toml'}: [operation 1] '{old}' is "
                              f"deprecated; use '{new}'"]
    else:
        unknown = f"operations[0].{new}: unknown key"
        assert [e for e in errs_new if e.startswith(unknown)]
        assert [e for e in errs_new if not e.startswith(unknown)] == \
            [e for e in errs_old if not e.startswith(f"operations[0].{old}:")]
        assert f"operations[0].{old}: '{old}' is now '{new}', which {op_type} operations " \
               f"do not take" in errs_old
        assert not warned_old


def test_features_keeps_step_for_its_step_file(tmp_path):
    errs, warned, got = _outcome({"type": "features", "step": "part.stp"}, tmp_path)
    assert not errs and not warned and got["step"] == tmp_path / "part.stp"


@pytest.mark.parametrize("op_type,old,new", list(_cases()))
def test_old_name_maps_to_the_new_one_and_warns(op_type, old, new, tmp_path):
    body = {k: v for k, v in BASE[op_type].items() if k != new}
    op = {"type": op_type, **body, old: VALUE[new]}
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        job = job_from_dict(_job(op), tmp_path / "job.toml")
    mine = [str(w.message) for w in got if issubclass(w.category, MillpathWarning)]
    assert mine == [f"{tmp_path / 'job.toml'}: [operation 1] '{old}' is deprecated; "
                    f"use '{new}'"]
    op_type_got, params = job.operations[0]
    assert op_type_got == op_type and params[new] == VALUE[new] and old not in params
    with warnings.catch_warnings():
        warnings.simplefilter("error", MillpathWarning)      # the new name: no warning
        job2 = job_from_dict(_job({"type": op_type, **body, new: VALUE[new]}),
                             tmp_path / "job.toml")
    assert job2.operations[0][1] == params


@pytest.mark.parametrize("op_type,old,new", list(_cases()))
def test_both_names_is_an_error_naming_both(op_type, old, new, tmp_path):
    body = {k: v for k, v in BASE[op_type].items() if k != new}
    op = {"type": op_type, **body, old: VALUE[new], new: VALUE[new]}
    with pytest.raises(JobError) as e:
        job_from_dict(_job(op), tmp_path / "job.toml")
    assert f"'{old}'" in e.value.message and f"'{new}'" in e.value.message
    assert e.value.message.startswith(f"operations[0].{old}:")


def test_warning_is_one_line_on_the_command_line(tmp_path):
    import subprocess
    import sys
    job = tmp_path / "job.toml"
    job.write_text('units = "mm"\n[stock]\nbox = [0, 0, -10, 40, 30, 0]\n[[tools]]\n'
                   'number = 1\ntype = "flat"\ndiameter = 6\n[[operations]]\n'
                   'type = "die-cavity"\ntool = 1\npoints = [[0, 0], [40, 0], [40, 30], '
                   '[0, 30]]\ndepth = 5\nstep_down = 6\ntolerance = 0.01\nfeed = 600\n'
                   'spindle = 8000\n[[operations]]\ntype = "die-cavity"\ntool = 1\n'
                   'points = [[0, 0], [40, 0], [40, 30], [0, 30]]\ndepth = 5\n'
                   'stepdown = 6\nstep_down = 6\ntolerance = 0.01\nfeed = 600\n')
    p = subprocess.run([sys.executable, "-m", "millpath.cli.main", "run", str(job), "-o", str(tmp_path / "out"), "--quiet"],
                       capture_output=True, text=True, timeout=120)
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 1 and not (tmp_path / "out").exists()
    assert lines == [f"millpath: warning: {job}: [operation 1] 'step_down' is deprecated; "
                     f"use 'stepdown'",
                     f"millpath: error: {job}:23: operations[1].step_down: 'step_down' and "
                     f"'stepdown' "
                     f"are the same key ('step_down' is the deprecated name); give only "
                     f"'stepdown'"]
