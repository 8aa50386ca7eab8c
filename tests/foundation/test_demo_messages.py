"""``millpath demo``'s messages are printed as written: an install hint such as
``pip install 'millpath[step-brep]'`` keeps its brackets (rich would read them as markup)."""

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
