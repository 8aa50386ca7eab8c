"""LinuxCNC tool tables and the TOML tool library round-trip."""

import pytest

from millpath.errors import JobError, MillpathError
from millpath.io.toollib import read_tool_library, write_tool_library
from millpath.io.tooltable import (ToolEntry, entries_from_tools, format_tool_table,
                                   parse_tool_table)
from millpath.model import Tool


def test_tool_table_written_then_read_back_is_equal():
    entries = [ToolEntry(1, 1, 6.0, {"Z": 50.0}, comment="flat 6"),
               ToolEntry(7, 3, 0.25, {"X": 0.1, "Z": -1.5}, comment="ball"),
               ToolEntry(12, 12, 10.5, {"Z": 123.456789})]
    text = format_tool_table(entries)
    assert text.splitlines()[0] == "T1 P1 Z50 D6 ;flat 6"
    assert parse_tool_table(text) == entries


def test_tool_table_reads_linuxcnc_style_lines():
    text = "T1 P1 D6.000 Z50.000 ;comment here\n\n; a comment line\nt2 p5 z+12.5 d-3\n"
    e = parse_tool_table(text)
    assert [x.number for x in e] == [1, 2]
    assert e[0].diameter == 6.0 and e[0].z == 50.0 and e[0].comment == "comment here"
    assert e[1].pocket == 5 and e[1].diameter == -3.0 and e[1].z == 12.5


@pytest.mark.parametrize("text, message", [
    ("T1 P1 D6 Z50\nT1 P2 D3", "tool 1 listed twice"),
    ("T1 P1 Dabc", "bad number"),
    ("P1 D3", "without a T word"),
    ("T1 P1 R3", "unknown word"),
    ("T1.5 P1", "non-negative integer"),
])
def test_tool_table_errors_name_the_line(text, message):
    with pytest.raises(MillpathError) as e:
        parse_tool_table(text, "tools.tbl")
    assert message in str(e.value)
    assert str(e.value).startswith("tools.tbl:")


def test_tool_library_round_trip(tmp_path):
    tools = {1: Tool(1, "flat", 6.0, flutes=3, flute_length=18, stickout=30,
                     holder=[(20, 40), (40, 60)]),
             2: Tool(2, "bull", 10.0, corner_radius=1.0, stickout=40, flute_length=25),
             3: Tool(3, "ball", 6.0, stickout=35, flute_length=12, shank_diameter=6.0),
             4: Tool(4, "drill", 8.5, point_angle=135, stickout=60, flute_length=50,
                     material="hss", comment="jobber")}
    p = tmp_path / "lib.toml"
    p.write_text(write_tool_library(tools))
    assert read_tool_library(p) == tools


def test_tool_library_rejects_unknown_key(tmp_path):
    p = tmp_path / "lib.toml"
    p.write_text('[[tools]]\nnumber = 1\ndiameter = 6\ncolour = "red"\n')
    with pytest.raises(JobError, match=r"tools\[0\]\.colour: unknown key"):
        read_tool_library(p)


def test_entries_from_tools_use_gauge_length_and_diameter():
    t = Tool(3, "flat", 6.0, stickout=30, flute_length=10, holder=[(20, 40), (40, 60)])
    (e,) = entries_from_tools({3: t})
    assert e.number == 3 and e.diameter == 6.0 and e.z == pytest.approx(130.0)
