"""Part 21 reader and writer: grammar, values, complex instances, errors, round trips."""

from __future__ import annotations

from pathlib import Path

import pytest

from millpath.errors import MillpathError
from millpath.part.step.p21 import DERIVED, Binary, Enum, Ref, Typed, parse, read
from millpath.part.step.writer import encode_string, format_real, write

FIXTURES = Path(__file__).parent / "fixtures"


def wrap(data: str, header: str = "FILE_SCHEMA(('TEST'));") -> str:
    return f"ISO-10303-21;\nHEADER;\n{header}\nENDSEC;\nDATA;\n{data}\nENDSEC;\nEND-ISO-10303-21;\n"


def test_every_value_kind_is_typed():
    sf = parse(wrap("#1=A(12,-3,1.5,-2.5E-3,1.E2,'it''s',.T.,.UNKNOWN.,$,*,\"0F1\","
                    "(1,(2.0,#1)),LENGTH_MEASURE(12.5),());"))
    p = sf[1].params
    assert p[0] == 12 and type(p[0]) is int
    assert p[1] == -3 and type(p[1]) is int
    assert p[2] == 1.5 and type(p[2]) is float
    assert p[3] == pytest.approx(-0.0025) and p[4] == 100.0 and type(p[4]) is float
    assert p[5] == "it's"
    assert isinstance(p[6], Enum) and p[6] == "T" and isinstance(p[7], Enum)
    assert p[8] is None and p[9] is DERIVED
    assert isinstance(p[10], Binary) and p[10] == "0F1"
    assert p[11] == [1, [2.0, Ref(1)]] and isinstance(p[11][1][1], Ref)
    assert p[12] == Typed("LENGTH_MEASURE", 12.5)
    assert p[13] == []


def test_string_escapes_decode():
    sf = parse(wrap(r"#1=A('\X2\00E9\X0\t\X\E9 \\ \S\a \X4\0001F600\X0\ \PA\x');"))
    assert sf[1].params[0] == "\u00e9t\u00e9 \\ \u00e1 \U0001F600 x"


def test_complex_instance_keeps_records_in_order():
    text = wrap("#15=DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.);\n"
                "#482=(LENGTH_MEASURE_WITH_UNIT()MEASURE_REPRESENTATION_ITEM()\n"
                "  MEASURE_WITH_UNIT(LENGTH_MEASURE(12.50),#15)REPRESENTATION_ITEM('height'));")
    inst = parse(text)[482]
    assert inst.complex
    assert inst.names() == ["LENGTH_MEASURE_WITH_UNIT", "MEASURE_REPRESENTATION_ITEM",
                            "MEASURE_WITH_UNIT", "REPRESENTATION_ITEM"]
    assert inst.get("MEASURE_WITH_UNIT") == [Typed("LENGTH_MEASURE", 12.5), Ref(15)]
    assert inst.get("REPRESENTATION_ITEM") == ["height"]
    assert inst.get("NOPE") is None


def test_records_span_lines_and_comments_are_skipped():
    sf = parse(wrap("/* a comment; with ; semicolons */\n#1=POINT(\n  'p', /* x */\n"
                    "  (1.0,\n   2.0));\n#2=LINE(#1,\n#1);"))
    assert sf[1].params == ["p", [1.0, 2.0]]
    assert sf.line_of(sf[2]) == 11


def test_inverse_references_and_by_type():
    sf = parse(wrap("#1=P(1);#2=Q(#1,(#1));#3=R(#2,#1);#4=(Q(#3)S());"))
    assert [i.id for i in sf.inverse(1)] == [2, 3]
    assert [i.id for i in sf.by_type("Q")] == [2, 4]
    assert [i.id for i in sf.users(2, "R", 0)] == [3]
    assert sf.users(1, "R", 0) == []


def test_header_is_parsed():
    sf = parse(wrap("#1=A();", "FILE_DESCRIPTION(('d'),'2;1');FILE_NAME('n','t',('a'),('o'),"
                    "'p','s','x');FILE_SCHEMA(('FEATURE_BASED_PROCESS_PLANNING'));"))
    assert sf.schemas == ["FEATURE_BASED_PROCESS_PLANNING"]
    assert sf.header_record("FILE_DESCRIPTION") == [["d"], "2;1"]


@pytest.mark.parametrize("data, message, line, entity", [
    ("#1=A(1);\n#2=B('open);\n", "unterminated string", 7, "#2"),
    ("#1=A(1);\n#2=B(#7);\n", "dangling reference #7", 7, "#2"),
    ("#1=A(1);\n#2=B(1.2.3);\n", "bad number '1.2.3'", 7, "#2"),
    ("#1=A(1);\n#2=B(12abc);\n", "bad number '12abc'", 7, "#2"),
    ("#1=A(1);\n#2=B(1,,2);\n", "missing value", 7, "#2"),
    ("#1=A(1);\n#1=B(2);\n", "defined twice", 7, "#1"),
])
def test_malformed_input_names_line_and_instance(data, message, line, entity):
    with pytest.raises(MillpathError) as e:
        parse(wrap(data), "part.stp")
    assert message in e.value.message
    assert e.value.file == "part.stp" and e.value.line == line and e.value.entity == entity
    assert str(e.value).startswith(f"part.stp:{line}: {entity}: ")


@pytest.mark.parametrize("cut", [40, 60, -30, -12])
def test_truncated_file_is_reported(cut):
    text = wrap("#1=A(1,2);\n#2=B(#1,'x');\n#3=C((1.0,2.0),#2);")
    with pytest.raises(MillpathError) as e:
        parse(text[:cut], "t.stp")
    assert e.value.line is not None and e.value.file == "t.stp"


def test_truncated_inside_instance_names_it():
    with pytest.raises(MillpathError) as e:
        parse(wrap("#1=A(1);\n#2=B((1,2").split("\nENDSEC;\nEND")[0], "t.stp")
    assert "truncated" in e.value.message and e.value.entity == "#2"


def test_not_a_step_file():
    with pytest.raises(MillpathError, match="not an ISO 10303-21 file"):
        parse("hello;", "x.stp")


def test_missing_file_is_a_user_error(tmp_path):
    with pytest.raises(MillpathError, match="no such STEP file"):
        read(tmp_path / "none.stp")


def test_reals_and_strings_are_written_in_part21_form():
    assert format_real(1.0) == "1.0" and format_real(1e-05) == "1.E-05"
    assert format_real(-2.5e20) == "-2.5E+20"
    assert encode_string("it's \\ \u00e9") == "'it''s \\\\ \\X2\\00E9\\X0\\'"
    with pytest.raises(ValueError):
        format_real(float("nan"))


def test_round_trip_keeps_value_kinds():
    text = wrap("#1=A(1,1.,'1',.T.,#1,$,*,\"1\",(1,1.),X(1));#2=(B(1)C('\\X2\\00E9\\X0\\'));")
    sf = parse(text)
    again = parse(write(sf))
    assert again.graph() == sf.graph()
    # kinds matter: an integer is not a real, a reference not an integer
    assert parse(wrap("#1=A(1);")).graph() != parse(wrap("#1=A(1.);")).graph()
    assert parse(wrap("#1=A(#1);")).graph() != parse(wrap("#1=A(1);")).graph()


def _round_trip(path: Path) -> None:
    sf = read(path)
    text = write(sf)
    again = parse(text, "written")
    assert again.graph() == sf.graph()
    assert write(again) == text


def test_shared_files_round_trip(shared_dir):
    files = sorted((shared_dir / "step").glob("*.stp")) + sorted((shared_dir / "step").glob("*.p21"))
    assert len(files) >= 7
    for f in files:
        _round_trip(f)


@pytest.mark.parametrize("name", sorted(p.name for p in FIXTURES.glob("*.stp")))
def test_fixtures_round_trip(name):
    _round_trip(FIXTURES / name)


def test_shared_instance_counts(shared_dir):
    assert len(read(shared_dir / "step" / "ap224_995277945.stp")) == 2266
    assert len(read(shared_dir / "step" / "iso14649_teste_final_unblab.p21")) == 468


def test_strings_broken_across_lines_drop_the_line_breaks():
    assert parse(wrap("#1=A('a long\n string');"))[1].params == ["a long string"]


def test_a_quote_left_open_is_reported_where_it_opens():
    with pytest.raises(MillpathError) as e:
        parse(wrap("#1=A(1);\n#2=B('x);\n#3=C('y');\n#4=D(2);"), "q.stp")
    assert (e.value.line, e.value.entity, e.value.message) == (7, "#2", "unterminated string")
