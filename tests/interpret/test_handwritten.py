"""Hand-written programs covering every language item, run through our interpreter and
LinuxCNC's rs274: same motion (1e-4) or an error on the same block."""

from __future__ import annotations

import pytest

from support.difftest import differential
from millpath.io.tooltable import ToolEntry

# tool table in inches (rs274's machine units): T1 D0.25, T2 negative diameter (other
# side), T3 large, T4 with X and Z offsets
TOOLS = [ToolEntry(1, 1, 0.25, {"Z": 1.0}), ToolEntry(2, 2, -0.1, {"Z": 0.5}),
         ToolEntry(3, 3, 1.0, {"Z": 2.0}), ToolEntry(4, 4, 0.125, {"X": 0.1, "Z": 1.5})]

P = {}
P["comments_case_spaces"] = """%
( header ) g21 f 100 ; trailing comment
N10 G0 x 1 . 5 y2(mid)z3
/G1 X2 (block delete is off in rs274)
n20 g1 X3 Y[1+2]
%
"""
P["parameters_expressions"] = """G21 F100
#1 = 3 #2 = [#1 * 2] (set after the line)
G0 X#1 Y#2
#<depth> = -1.5
G1 Z#<depth> X[sin[30]*10] Y[cos[60]*10]
G1 X[atan[1]/[1]] Y[sqrt[2]**2] Z[abs[-2]]
G1 X[fix[2.7]] Y[fup[2.1]] Z[round[2.5]]
G1 X[exp[1]] Y[ln[10]] Z[10 mod 3]
G1 X[1 eq 1] Y[2 gt 1] Z[[1 lt 2] and [0 or 1]]
G1 X[asin[0.5]] Y[acos[0.5]] Z[tan[45]]
G1 X[1 + 2 * 3 - 4 / 2] Y[2 ** 3 ** 2] Z[-[1+1]]
M2
"""
P["modal_conflict_g"] = "G21\nG0 G1 X1\nM2\n"
P["modal_conflict_m"] = "G21\nM3 M5\nM2\n"
P["g80_gives_way"] = "G21 F10\nG0 G80 X1\nG80 G1 X2\nM2\n"
P["unknown_g"] = "G21\nG7.5 X1\nM2\n"
P["unknown_m"] = "G21\nM77\nM2\n"
P["multiple_words"] = "G21\nG0 X1 X2\nM2\n"
P["bad_number"] = "G21\nG0 X1.2.3\nM2\n"
P["unclosed_comment"] = "G21\nG0 X1 (oops\nM2\n"
P["divide_by_zero"] = "G21\nG0 X[1/0]\nM2\n"
P["axis_without_motion"] = "G21\nX1\nM2\n"
P["axis_with_g80"] = "G21\nG80 X1\nM2\n"
P["two_axis_codes"] = "G21\nG92 G0 X1\nM2\n"
P["zero_feed"] = "G21\nG1 X1\nM2\n"
P["word_unused"] = "G21\nG0 X1 Q2\nM2\n"
P["no_program_end"] = "G21\nG0 X1\n"
P["lines_units"] = """G20 F10
G0 X1 Y1 Z1
G1 X2 Y2 Z0
G21
G1 X0 Y0
G91 G1 X10 Y-5
G90 G0 X0 Y0
M2
"""
P["arcs_xy_ijk_r"] = """G21 F100
G0 X0 Y0 Z0
G2 X10 Y0 I5 J0
G3 X0 Y0 R5
G3 X10 Y0 R-5
G2 X10 Y0 I-5 J0 P2
G3 X20 Y10 Z-5 I0 J10
G2 X10 Y0 R-10
M2
"""
P["arcs_xz_yz"] = """G20 F10
G0 X0 Y0 Z0
G18 G2 X1 Z1 I0.5 K0.5
G3 X0 Z0 R0.7071
G2 X0 Z0 Y1 I0.5 K0 P2
G19 G3 Y1 Z0 J0.5 K-0.5
G2 Y0 Z0 X2 R0.6
G17 G0 X1 Y0
G2 X0 Y1 Z2 I-1 J0
M2
"""
P["arc_absolute_center"] = """G21 F100 G90.1
G0 X10 Y0
G3 X0 Y10 I0 J0
G91.1 G3 X-10 Y0 I0 J-10
M2
"""
P["arc_radius_differs"] = "G21 F100\nG0 X0 Y0\nG2 X10 Y1 I5 J0\nM2\n"
P["arc_radius_too_small"] = "G21 F100\nG0 X0 Y0\nG2 X10 Y0 R4\nM2\n"
P["arc_k_in_xy"] = "G21 F100\nG2 X1 K1\nM2\n"
P["arc_no_center"] = "G21 F100\nG2 X1 Y1\nM2\n"
P["arc_mixed"] = "G21 F100\nG2 X1 Y1 R1 I1\nM2\n"
P["arc_zero_radius"] = "G21 F100\nG0 X0 Y0\nG2 X0 Y0 I0 J0.00001\nM2\n"
P["arc_same_point_r"] = "G21 F100\nG0 X1 Y1\nG2 X1 Y1 R2\nM2\n"
P["arc_p_not_integer"] = "G21 F100\nG2 X1 Y0 R1 P1.5\nM2\n"
P["dwell"] = "G21 F100\nG0 X1\nG4 P0.5\nG1 X2\nG4\nM2\n"
P["inverse_time"] = "G21\nG93 G1 X10 F2\nG2 X20 Y0 R5 F1\nG1 X30\nM2\n"
P["work_offsets"] = """G21 F100
G0 X0 Y0 Z5
G10 L2 P2 X10 Y5 Z-1
G10 L2 P1 X1
G55 G0 X0 Y0
G1 X1 Y1
G10 L20 P2 X0 Y0
G1 X2
G56 G0 X0
G54 G0 X0 Y0
G53 G0 X5 Y5 Z0
G59.3 G0 X1
M2
"""
P["g92_family"] = """G21 F100
G0 X5 Y5
G92 X0 Y0
G1 X1 Y1
G92.2
G1 X2
G92.3
G1 X3
G92.1
G1 X4
G52 X1 Y1
G0 X0 Y0
M2
"""
P["tools_g43"] = """G21
T1 M6
G43
G0 X0 Y0 Z0
T4 M6
G43 H4
G0 X1
G43 H1
G0 X2
G49
G0 X3
G43.1 Z2 X1
G0 X4
G43.2 H1
G0 X5
G49 G20
G0 X1
M2
"""
P["tool_not_found"] = "G21\nT9\nM2\n"
P["h_not_found"] = "G21\nG43 H9\nM2\n"
P["spindle_coolant"] = ("G21 F100 S1200 M3 M8\nG1 X1\nM4 S500\nG1 X2\nM5 M9\nM7\nG1 X3\nM0\n"
                        "M1\nM30\n")
P["cycles_xy"] = """G21 F100
G0 X0 Y0 Z5
G81 X1 Y1 Z-2 R1
X2
G98 G82 X3 Z-2 R1 P0.5
G99 G83 X4 Y1 Z-3 R1 Q0.7
G73 X5 Z-3 R1 Q0.8
G85 X6 Z-1 R2
G89 X7 Z-1 R2 P0.2
G91 G81 X1 Y1 Z-3 R-2 L3
G90 G80
G0 Z1
G98 G81 X1 Y1 Z-1 R3
G80
M2
"""
P["cycles_other_planes"] = """G20 F10
G0 X0 Y0 Z0
G18 G81 X1 Z1 Y-1 R0.5
G83 X2 Z1 Y-1 R0.5 Q0.3
G19 G81 Y1 Z1 X-1 R0.5
G98 G73 Y2 Z2 X-1 R0.5 Q0.4
G17 G80
M2
"""
P["cycle_r_missing"] = "G21 F100\nG81 X1 Z-1\nM2\n"
P["cycle_z_missing"] = "G21 F100\nG81 X1 R1\nM2\n"
P["cycle_r_below_z"] = "G21 F100\nG81 X1 Z2 R1\nM2\n"
P["cycle_q_missing"] = "G21 F100\nG83 X1 Z-1 R1\nM2\n"
P["cycle_zero_feed"] = "G21\nG81 X1 Z-1 R1\nM2\n"
P["cycle_l0"] = "G21 F100\nG81 X1 Z-1 R1 L0\nM2\n"
P["comp_square_left"] = """G21 F100
G0 X-10 Y-10
G41 D1
G1 X0 Y0
G1 X20
G1 Y20
G1 X0
G1 Y0
G40 G1 X-10 Y-10
M2
"""
P["comp_square_right_convex_arcs"] = """G20 F10
G0 X-1 Y-1
G42 D1
G1 X0 Y0
G1 Y2
G1 X2
G1 Y0
G1 X0
G40 G0 X-1 Y-1
M2
"""
P["comp_negative_diameter"] = """G20 F10
G0 X-1 Y-1
G41 D2
G1 X0 Y0
G1 X2
G1 Y2
G40 G1 X3 Y3
M2
"""
P["comp_with_arcs"] = """G21 F100
G0 X-10 Y-10 Z5
G41 D1
G1 X0 Y0
G1 Z-1
G1 X20
G3 X20 Y20 R10
G1 X0 Y20
G3 X0 Y0 I0 J-10
G40 G1 X-10 Y-10
M2
"""
P["comp_arc_first"] = """G21 F100
G0 X0 Y-20
G42 D1
G2 X20 Y0 I0 J20
G1 X20 Y20
G40 G1 X30 Y30
M2
"""
P["comp_concave_arc_corners"] = """G21 F100
G0 X-5 Y-5
G41 D1
G1 X0 Y0
G1 X30
G3 X20 Y10 R10
G2 X10 Y20 R10
G1 X0 Y20
G1 Y0
G40 G1 X-5 Y-5
M2
"""
P["comp_z_and_skip_moves"] = """G21 F100
G0 X-10 Y-10 Z5
G42 D1
G1 X0 Y0
G1 Z-1
G1 X10 Y0
G1 Z-2
G1 X10 Y0
G4 P1
F200
G1 X10 Y10
G1 Z5
G40 G0 X20 Y20
M2
"""
P["comp_g41_1"] = """G21 F100
G0 X-10 Y0
G41.1 D4
G1 X0 Y0
G1 X10
G1 Y10
G40 G1 X20 Y20
M2
"""
P["comp_xz_plane"] = """G20 F10
G18
G0 X0 Z2
G41 D1
G1 X1 Z0
G1 X2 Z-1
G2 X3 Z-2 R1
G40 G1 X4 Z0
M2
"""
P["comp_entry_too_short"] = "G20 F10\nG0 X0 Y0\nG41 D3\nG1 X0.3 Y0\nM2\n"
P["comp_already_on"] = "G21 F10\nG41 D1\nG42 D1\nM2\n"
P["comp_yz_plane"] = "G21 F10\nG19 G41 D1\nM2\n"
P["comp_plane_change"] = "G21 F10\nG41 D1\nG18\nM2\n"
P["comp_tool_change"] = "G21 F10\nG41 D1\nT1 M6\nM2\n"
P["comp_cycle"] = "G21 F10\nG41 D1\nG81 X1 Z-1 R1\nM2\n"
P["comp_g92"] = "G21 F10\nG41 D1\nG92 X0\nM2\n"
P["comp_coord_change"] = "G21 F10\nG41 D1\nG55\nM2\n"
P["comp_g43"] = "G21 F10\nG41 D1\nG43 H1\nM2\n"
P["comp_g53"] = "G21 F10\nG0 X-10\nG41 D1\nG1 X0\nG53 G1 X5\nM2\n"
P["comp_arc_after_g40"] = "G20 F10\nG0 X-1\nG41 D1\nG1 X0 Y0\nG1 X2\nG40\nG2 X3 Y1 R1\nM2\n"
P["comp_tool_bigger_than_arc"] = """G20 F10
G0 X-1 Y0
G41 D3
G1 X0 Y0
G3 X0.6 Y0 R0.3
M2
"""
P["comp_concave_gouge"] = """G20 F10
G0 X-1 Y-1
G41 D3
G1 X0 Y0
G1 X2
G1 X2.1 Y0.1
G1 X2.2 Y0
G1 X4
M2
"""
P["comp_d_not_found"] = "G21\nG41 D9\nM2\n"
P["comp_d_fraction"] = "G21\nG41 D1.5\nM2\n"
P["spline_g5"] = """G21 F100
G0 X0 Y0
G5 X10 Y0 I2 J5 P-2 Q5
G5 X20 Y0 P-2 Q-5
G5.1 X30 Y0 I5 J5
G1 X40
M2
"""
P["spline_errors"] = "G21 F100\nG5 X10 Y0 I2 P-2 Q5\nM2\n"
P["g28_g30"] = "G21\nG0 X5 Y5 Z5\nG28.1\nG0 X1\nG28 Z2\nG28\nG30\nM2\n"
P["g10_l1_tool"] = "G21\nG10 L1 P1 Z2 R0.2\nT1 M6 G43\nG0 Z0\nM2\n"


@pytest.mark.parametrize("name", sorted(P))
def test_same_as_rs274(rs274, name):
    c = differential(P[name], TOOLS, machine_units="inch")
    assert c.same, f"{name}:\n{c}"
    if c.ours_error:
        assert c.ours_error[1] == c.their_error[1]


SHOULD_RUN = ("comments_case_spaces", "parameters_expressions", "lines_units", "arcs_xy_ijk_r",
              "arcs_xz_yz", "arc_absolute_center", "work_offsets", "g92_family", "tools_g43",
              "spindle_coolant", "cycles_xy", "cycles_other_planes", "comp_square_left",
              "comp_square_right_convex_arcs", "comp_negative_diameter", "comp_with_arcs",
              "comp_arc_first", "comp_concave_arc_corners", "comp_z_and_skip_moves",
              "comp_g41_1", "comp_xz_plane", "spline_g5", "g28_g30", "g10_l1_tool",
              "g80_gives_way")


@pytest.mark.parametrize("name", SHOULD_RUN)
def test_programs_meant_to_run_run_without_error(name):
    from millpath.interpret import run
    r = run(P[name], TOOLS)
    assert r.error is None and len(r.motions) > 0


P2 = {}
P2["tool_change_resync"] = """G20
G0 X0 Y0 Z0
T1 M6
G43 H1
G0 X1
T4 M6 G43 H4
G0 X2
T1 M6 G43 H1 G92 X5
G0 Y1
T4 M6 G43 H4 G0 X2
G0 Y2
G4 P1 T1 M6 G43 H1
G0 X0
M2
"""

P2["g51_then_m61"] = """G21 F100
G0 X0 Y0
G5.1 X10 Y0 I5 J5
M61 Q2
G43
G0 Z1
M2
"""
P2["g28_g30_axes"] = """G20 F10
G0 X1 Y1 Z1
G28 X0
G30 Y0
G28.1
G30.1
G0 X2
G28
M2
"""
P2["incremental_arcs"] = """G21 F100
G91 G0 X1 Y1
G91 G2 X2 Y0 I1 J0
G90 G3 X0 Y0 R3
G91 G1 X-1
G90
M2
"""
P2["comp_full_circle_p2"] = """G21 F100
G0 X-10 Y0
G41 D1
G1 X0 Y0
G3 X0 Y0 I10 J0 P2
G40 G1 X-10
M2
"""
P2["comp_tangent_arcs"] = """G21 F100
G0 X-10 Y0
G41 D1
G1 X0 Y0
G2 X20 Y0 I10 J0
G3 X40 Y0 I10 J0
G1 X50
G40 G1 X60 Y10
M2
"""
P2["comp_incremental"] = """G21 F100
G0 X-10 Y-10
G42 D1
G91 G1 X10 Y10
G1 X10
G1 Y10
G90 G40 G1 X-10 Y-10
M2
"""
P2["comp_queue_with_spindle_coolant_feed"] = """G21 F100
G0 X-10 Y-10
G41 D1
G1 X0 Y0
G1 X10 M3 S1000
M8
G1 X10 Y10 F50
G40 G0 X20
M2
"""
P2["comp_units_switch"] = """G21 F100
G0 X0 Y0
G41 D1
G1 X10 Y0
G20
G1 X1 Y1
G40 G1 X2 Y2
M2
"""
P2["comp_z_rapids_m0"] = """G21 F100
G0 X0 Y0 Z1
G41 D1
G1 X10 Y0
G0 Z5
G0 X20 Y0
G1 Z-1
G1 X20 Y10
M0
G1 X0 Y10
G40 G1 X-5
M2
"""
P2["msg_print_comments"] = """G21
G0 X1 (msg, hello)
(print, hi)
G0 X2 ; comment
G0 X3 (a) (b)
M2
"""
P2["parameters_case_and_timing"] = """G21 F100
#1 = 5
#2 = [#1 + 1]
#3 = #2
G0 X#1 Y#2 Z#3
#<v> = 3
#<V> = 4
G0 X#<v>
M2
"""
P2["g10_l20_with_g92"] = """G21 F100
G0 X0 Y0
G10 L2 P1 X5 Y5 Z0
G0 X1 Y1
G10 L20 P1 X0 Y0
G0 X1
G92 X10
G10 L2 P1 X0 Y0
G0 X0
M2
"""
P2["cycle_incremental_repeats"] = """G21 F100
G0 X0 Y0 Z0
G81 X1 Y1 Z-1 R2 L3 G91
G90 G80
M2
"""
P2["absolute_arc_centers"] = """G21 F100
G0 X0 Y0 Z0
G1 X1 G90.1 
G2 X3 Y0 I2 J0
M2
"""
P2["r_arc_with_turns"] = """G21 F100
G0 X0 Y0 Z0
G1 X1 Y1
G2 X2 Y2 R1 P2
M2
"""
P2["g43_h0"] = """G21 F100
G0 X0 Y0
G43 H0
G1 X1
M2
"""
P2["g41_without_d_no_tool"] = """G21 F100
G0 X-10 Y0
G41
G1 X0
G1 X10
M2
"""
P2["g83_retract_modes"] = """G21 F100
G0 X0 Y0 Z5
G98 G83 X1 Y1 Z-5 R1 Q1
G99 X2
G98 Y2 Z-6 Q2
G80
M2
"""
P2["m61_then_comp_without_d"] = """G21 F100
G0 X0 Y0
G1 X10
M61 Q2
G43
G0 Z1
G41
G1 X20 Y5
G1 X30
G40 G1 X40
M2
"""
P2["m61_keeps_spindle_row"] = """G21 F100
T2 M6
M61 Q1
G43
G0 X1
M2
"""

P2["owords_sub_while_if_repeat_do"] = """G21 F100
o<sq> sub
  G1 X#1 Y0
  G1 X#1 Y#1
  G1 X0 Y#1
  G1 X0 Y0
o<sq> endsub [#1 * 2]
#5 = 0
o10 while [#5 lt 3]
  o<sq> call [[#5 + 1] * 10]
  #5 = [#5 + 1]
o10 endwhile
o20 if [#<_value> gt 50]
  G0 Z10
o20 else
  G0 Z20
o20 endif
o30 repeat [2]
  G0 X1
o30 endrepeat
o40 do
  #5 = [#5 - 1]
  G0 Y#5
o40 while [#5 gt 0]
M2
"""
P2["owords_return_elseif_break_locals"] = """G21 F100
#1 = 7
o100 sub
  #<loc> = 5
  G0 X[#1 + #<loc>]
  o101 if [#1 gt 2]
    o100 return [3]
  o101 endif
  G0 Y1
o100 endsub
o100 call [1]
o100 call [4]
G0 X#1 Y#<_value>
o200 if [0]
  G0 X99
o200 elseif [1]
  G0 X50
o200 else
  G0 X60
o200 endif
#2 = 0
o300 while [1]
  #2 = [#2 + 1]
  o301 if [#2 gt 3]
    o300 break
  o301 endif
  G0 Z#2
o300 endwhile
M2
"""
P2["owords_nested_sub_error"] = ("G21\nO1 sub\nG1 X0\n  O2 sub\n  G1 Y0\n  O2 endsub\n"
                                 "O1 endsub\nO1 call\nM30\n")

P2["polar_cycles_and_moves"] = """G20 F10
G0 X0 Y0 Z0
G0 X2.5 Y0
G81 R.1 Z-0.5 F60
^120
^240
G90 @1 ^33
G91 G81 @1 R.1 Z-0.5 L5
G90 G0 X2 Y0
G91 G81 ^[360/17] R.1 Z-0.5 L17
G90 G80 G0 X1 Y1
G1 @2
G91 G1 @-.1 ^4.5
G1 ^10
G90 G2 @1 ^90 R1
G0 @1 ^0
G91 G3 ^90 @0.5 R0.8
M2
"""
P2["polar_radius_only"] = """G21
G0 X0 Y0
G1 @1 F10
M2
"""
P2["polar_with_x_error"] = """G21
G0 @1 X1
M2
"""
P2["polar_outside_g17_error"] = """G21 G18
G0 @1
M2
"""
P2["polar_without_motion_error"] = """G21
@1
M2
"""

P2["xy_rotation_offsets_g53_g28_tlo"] = """G21 F100
G10 L2 P2 X10 Y5 R30
G10 L2 P1 R15
G0 X1 Y1
G55 G0 X2 Y0
G1 X5 Y5
G2 X7 Y5 R1
G10 L20 P2 X0 Y0
G1 X3
G54 G0 X0 Y0
G53 G0 X5 Y5
G55
G53 G0 X1
T4 M6 G43 H4
G0 X4
G28.1
G0 X0 Y0
G28
G92 X1 Y1
G0 X2
G10 L2 P0 R-20
G0 X3 Y3
M2
"""
P2["xy_rotation_l20_and_switching"] = """G20 F10
G10 L2 P1 X1 Y1 R90
G0 X1 Y0
G10 L20 P1 X0
G0 Y1
G56 G0 X0
G10 L2 P3 R45
G0 X1
G54
G0 X1
M2
"""

P2["g10_l1_l10_l11_tool_offsets"] = """G20 F10
G0 X1 Y2 Z3
T1 M6 G43
G10 L10 P1 Z0.5
G43
G0 X0
G10 L10 P4 X0.1 Y0.2
G10 L1 P4 Z1.2 R0.1
T4 M6 G43 H4
G0 X1
G10 L2 P9 X1 Y1 Z1 R10
G10 L11 P1 X0 Z2
G43 H1
G0 Y0
M2
"""

P2["system_parameters_position_tool_offsets"] = """G21 F100
G0 X1 Y2 Z3
G0 X[#5420+1] Y#5421 Z[#5422*2]
T1 M6
G0 X#5400
G55 G0 Y#5220
G92 X0
G0 Y[#5420+#5211]
M2
"""


@pytest.mark.parametrize("name", sorted(P2))
def test_more_same_as_rs274(rs274, name):
    c = differential(P2[name], TOOLS, machine_units="inch")
    assert c.same, f"{name}:\n{c}"
