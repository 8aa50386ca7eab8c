"""``millpath demo`` names each example as it starts and prints messages as written: an
install hint such as ``pip install 'millpath[step-brep]'`` keeps its brackets (rich
would read them as markup)."""

from __future__ import annotations

from click.testing import CliRunner

from millpath.cli.main import cli
from millpath.errors import MillpathError


def test_skip_message_keeps_the_extra_in_brackets(monkeypatch, tmp_path):
    import millpath.pipeline as pipeline
    from millpath.part.brep.reader import STEP_BREP_EXTRA

    def no_ocp(job, out, **kw):
        raise MillpathError(STEP_BREP_EXTRA, job)
    monkeypatch.setattr(pipeline, "run_job", no_ocp)
    r = CliRunner().invoke(cli, ["demo", "-o", str(tmp_path / "d"), "-k", "solid-hole"])
    text = " ".join(r.output.split())
    assert STEP_BREP_EXTRA in text, r.output
    assert "[step-brep]" in STEP_BREP_EXTRA


def test_demo_names_each_example_as_it_starts(monkeypatch, tmp_path):
    import millpath.pipeline as pipeline
    from millpath.part.brep.reader import STEP_BREP_EXTRA

    def no_ocp(job, out, **kw):
        raise MillpathError(STEP_BREP_EXTRA, job)
    monkeypatch.setattr(pipeline, "run_job", no_ocp)
    r = CliRunner().invoke(cli, ["demo", "-o", str(tmp_path / "d"), "-k", "solid-hole"])
    assert "solid-hole-model (1 of 1) ..." in r.output, r.output
