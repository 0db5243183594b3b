"""Tyre property files (.tir, MF 6.1/6.2): the one mapping table, exact round trips, the paper's Hopf speeds through
a written file, the published example tyre, units, scalings, axle files naming a tyre, and every kind of bad file."""

import dataclasses
import json
import pathlib

import pytest

from axles.axle import entries, paper_axle
from axles.axle_file import parse_axle
from axles.dimensions import DEFAULT_DIMENSIONS
from axles.parameters import YANG2024
from axles.tyre_file import TyreFileError, apply_tyre, format_tir, parse_tir, read_tir
from axles.tyre_mapping import AXLE, REQUIRED, TYRE_KEYS, ZERO
from comparisons.cli.main import main

DATA = pathlib.Path(__file__).resolve().parents[1] / "data"
PAPER_TIR = DATA / "yang2024-paper-tyre.tir"
EXAMPLE_TIR = DATA / "mf61-205-60R15-example.tir"


@pytest.fixture
def run(capsys):
    def call(*args):
        code = main(list(map(str, args)))
        out, err = capsys.readouterr()
        return code, out, err
    return call


def test_mapping_table_is_one_to_one_onto_axle_entries():
    names = [k.entry for k in TYRE_KEYS]
    assert len(names) == len(set(names)) and set(names) <= set(entries())
    assert len({(k.section, k.key) for k in TYRE_KEYS}) == len(TYRE_KEYS)
    assert {k.missing for k in TYRE_KEYS} == {REQUIRED, ZERO, AXLE}
    # the paper's p_ky3 is MF 6.1's PKY4; PKY3 is the camber term; PKY1 changes sign
    row = {k.key: k for k in TYRE_KEYS}
    assert row["PKY4"].entry == "p_ky3" and row["PKY3"].entry == "camber_p_ky3" and row["PKY1"].sign == -1.0


def test_committed_paper_tyre_is_what_write_tir_writes(tmp_path, run):
    out = tmp_path / "paper.tir"
    assert run("params", "--write-tir", out)[0] == 0
    assert out.read_text() == PAPER_TIR.read_text() == format_tir(paper_axle())


def test_paper_tyre_round_trip_is_exact():
    tyre = read_tir(str(PAPER_TIR))
    assert tyre.unused == ("[OPERATING_CONDITIONS] INFLPRES",) and tyre.zeros == () and tyre.kept == ()
    axle = apply_tyre(paper_axle(), tyre)
    assert axle.params == YANG2024 and axle.dims == DEFAULT_DIMENSIONS


def test_paper_tyre_onto_another_axle_restores_every_tyre_entry():
    """Read onto an axle whose tyre entries all differ: every mapped entry comes back bit for bit."""
    other = paper_axle().with_values({k.entry: (entries()[k.entry].range_si[0] + entries()[k.entry].range_si[1]) / 2
                                      for k in TYRE_KEYS})
    back = apply_tyre(other, read_tir(str(PAPER_TIR)))
    for k in TYRE_KEYS:
        assert back.value(k.entry) == paper_axle().value(k.entry), k.key


def test_example_tyre_round_trip_reproduces_every_coefficient():
    """File -> axle -> file -> axle: every coefficient the axle holds, exactly (awkward decimals included)."""
    first = apply_tyre(paper_axle(), read_tir(str(EXAMPLE_TIR)))
    again = apply_tyre(paper_axle(), parse_tir(format_tir(first), "<written>"))
    assert again.params == first.params and again.dims == first.dims
    written = parse_tir(format_tir(first), "<written>")
    assert dict(written.values) == {k.entry: first.value(k.entry) for k in TYRE_KEYS}


def test_example_tyre_values_and_what_it_lacks():
    tyre = read_tir(str(EXAMPLE_TIR))
    axle = apply_tyre(paper_axle(), tyre)
    p, d = axle.params, axle.dims
    assert (p.p_ky1, p.p_ky3, p.Fz0, p.R, p.pi0, p.k5_0) == (15.324, 2.0005, 4000.0, 0.3135, 2e5, 209651.0)
    assert (p.p_py4, p.p_pz1, p.p_fz1, d.camber_p_ky3, d.camber_q_bz9) == (-0.2811, -0.4408, 0.7098, 0.3695, 34.5)
    # no [STRUCTURAL], no extensions: the relaxation law and the section 3 constants stay the axle's, and
    # Hopping's E_y terms are absent (MF 6.1's E_y)
    assert set(tyre.kept) == {"c_y0", "p_cy1_rl", "a0", "t0", "sigma0"}
    assert (p.c_y0, p.a0, p.t0, p.sigma0) == (YANG2024.c_y0, YANG2024.a0, YANG2024.t0, YANG2024.sigma0)
    assert set(tyre.zeros) == {"p_ey3", "p_epy1", "p_epy2", "p_epey1"} and p.p_epy1 == 0.0
    # keys neither model uses are listed, PFZ1 is found in the source's [LOADED_RADIUS_COEFFICIENTS]
    assert "[LATERAL_COEFFICIENTS] PEY3" in tyre.unused and "[LONGITUDINAL_COEFFICIENTS] PHX1" in tyre.unused
    # the longitudinal and combined-slip coefficients are read (braking), their shifts and camber terms are not
    assert (p.p_cx1, p.p_kx1, p.r_bx1, p.r_hx1, p.r_by3, p.r_vy6) == (1.579, 21.687, 13.046, -9.968e-5, 0.002037, 23.8)
    assert not any(u.endswith((" RBX1", " RBY1", " RVY1", " PCX1")) for u in tyre.unused)
    assert "[LATERAL_COEFFICIENTS] RVY3" in tyre.unused and "[LONGITUDINAL_COEFFICIENTS] RBX3" in tyre.unused
    assert not any(u.endswith(" PFZ1") or u.endswith(" PKY4") for u in tyre.unused)


def test_paper_tyre_through_tir_gives_the_paper_hopf_speeds(tmp_path, run):
    """The paper's tyre written as .tir and read back onto the paper's axle: Hopf speeds to 1e-9 km/h."""
    for pressure in ("1.5", "2.5"):
        for effects in ("", "all"):
            code, out, _ = run("hopf", "--pressure", pressure, "--effects", effects, "--json")
            built_in = json.loads(out)["hopf"]
            code2, out2, _ = run("hopf", "--pressure", pressure, "--effects", effects, "--tyre", PAPER_TIR, "--json")
            via_tir = json.loads(out2)["hopf"]
            assert code == code2 == 0 and len(built_in) == len(via_tir) >= 2
            for a, b in zip(built_in, via_tir):
                assert abs(a["speed_kmh"] - b["speed_kmh"]) <= 1e-9


def test_units_are_converted():
    """The same tyre in mm and kN (and the pressure in kN/mm^2, or by PRESSURE = 'Pa') reads to the same SI."""
    import re
    si = {"R": 0.4, "Fz0": 6000.0, "k5_0": 400000.0, "c_y0": 96920.0, "a0": 0.2, "t0": 0.07, "sigma0": 0.65}
    scale = {"UNLOADED_RADIUS": 1e3, "A0": 1e3, "T0": 1e3, "SIGMA0": 1e3, "FNOMIN": 1e-3,
             "VERTICAL_STIFFNESS": 1e-6, "LATERAL_STIFFNESS": 1e-6, "NOMPRES": 1e-9}
    text = PAPER_TIR.read_text().replace("'meter'", "'mm'").replace("'newton'", "'kN'")
    for key, factor in scale.items():
        text = re.sub(rf"^({key} +=) (\S+)", lambda m: f"{m.group(1)} {float(m.group(2)) * factor!r}", text,
                      flags=re.M)
    axle = apply_tyre(paper_axle(), parse_tir(text, "<mm>"))
    for name, value in si.items():
        assert axle.value(name) == pytest.approx(value, rel=1e-14), name
    assert axle.params.pi0 == pytest.approx(2.5e5, rel=1e-14)
    text = re.sub(r"^(NOMPRES +=) (\S+)", r"\1 36.25942", text, flags=re.M).replace("[UNITS]", "[UNITS]\nPRESSURE = 'psi'")
    assert apply_tyre(paper_axle(), parse_tir(text, "<psi>")).params.pi0 == pytest.approx(2.5e5, rel=1e-6)


def test_scaling_factors_are_folded_in_or_refused():
    text = PAPER_TIR.read_text()
    scaled = text.replace("LKY                      = 1.0", "LKY = 0.5")
    assert apply_tyre(paper_axle(), parse_tir(scaled, "<s>")).params.p_ky1 == YANG2024.p_ky1 * 0.5
    with pytest.raises(TyreFileError, match=r"<s>:\d+: \[SCALING_COEFFICIENTS\] LVY = 0.9: only 1"):
        parse_tir(text.replace("LVY                      = 1.0", "LVY = 0.9"), "<s>")


@pytest.mark.parametrize("name, message", [
    ("broken-missing-section.tir", r"broken-missing-section.tir: missing section \[ALIGNING_COEFFICIENTS\]$"),
    ("broken-non-numeric.tir", r"broken-non-numeric.tir:\d+: \[LATERAL_COEFFICIENTS\] PDY1 = '0.8.75' is not a "
                               r"number$"),
    ("broken-fittyp.tir", r"broken-fittyp.tir:\d+: \[MODEL\] FITTYP = 52: unknown FITTYP"),
    ("broken-units.tir", r"broken-units.tir:\d+: \[UNITS\] LENGTH = 'furlong': a unit it cannot convert"),
    ("broken-range.tir", r"broken-range.tir:\d+: \[LATERAL_COEFFICIENTS\] PKY1 = 12.0628 gives p_ky1 = -12.0628 "
                         r".*outside its physical range"),
])
def test_bad_file_is_one_line_and_exit_2(run, name, message):
    code, out, err = run("params", "--tyre", DATA / name)
    assert code == 2 and out == "" and len(err.splitlines()) == 1, err
    assert __import__("re").search(message, err.strip()), err


@pytest.mark.parametrize("edit, message", [
    (lambda t: t.replace("PCY1 ", "PCY1_GONE "), r"missing key \[LATERAL_COEFFICIENTS\] PCY1"),
    (lambda t: t + "[LATERAL_COEFFICIENTS]\n", r":\d+: section \[LATERAL_COEFFICIENTS\] given twice"),
    (lambda t: t.replace("PDY2 ", "PDY1 = 1.0\nPDY2 "), r":\d+: \[LATERAL_COEFFICIENTS\] PDY1 given twice"),
    (lambda t: t.replace("ANGLE                    = 'radians'", "ANGLE = 'degrees'"), "cannot convert"),
    (lambda t: t.replace("QEZ4                     = 0.2895", "QEZ4 = nan"), "not a finite number"),
])
def test_more_bad_files(edit, message):
    with pytest.raises(TyreFileError, match=message):
        parse_tir(edit(PAPER_TIR.read_text()), "<t>")


def test_not_a_regular_file_or_too_large(tmp_path, run):
    code, _, err = run("params", "--tyre", tmp_path)
    assert code == 2 and "is a directory, not a tyre file" in err
    big = tmp_path / "big.tir"
    big.write_text("!" * 1_000_001)
    code, _, err = run("params", "--tyre", big)
    assert code == 2 and "bytes, more than the" in err


def test_axle_file_names_a_tyre_relative_to_itself(tmp_path, run):
    (tmp_path / "tyres").mkdir()
    (tmp_path / "tyres" / "mine.tir").write_text(EXAMPLE_TIR.read_text())
    axle = parse_axle('name = "t"\nbase = "YANG2024"\ntyre_file = "tyres/mine.tir"\n',
                      source=str(tmp_path / "truck.toml"))
    assert axle.params == apply_tyre(paper_axle(), read_tir(str(EXAMPLE_TIR))).params
    assert axle.describe()["tyre_file"] == str(tmp_path / "tyres" / "mine.tir")
    from axles.axle_file import AxleFileError
    with pytest.raises(AxleFileError, match="p_ky1 is also given by tyre_file"):
        parse_axle('name = "t"\nbase = "YANG2024"\ntyre_file = "tyres/mine.tir"\n[table1]\np_ky1 = 12.0\n',
                   source=str(tmp_path / "truck.toml"))


def test_params_lists_the_tyre_and_writes_an_axle_file(tmp_path, run):
    toml = tmp_path / "mytruck.toml"
    code, out, _ = run("params", "--tyre", EXAMPLE_TIR, "--write", toml)
    assert code == 0 and "not in the file, kept from the axle: c_y0, p_cy1_rl, a0, t0, sigma0" in out
    assert "[LONGITUDINAL_COEFFICIENTS] PDX3, PHX1" in out and "trail 0.0417566 m (t0 = 0.07 m)" in out
    from axles.axle_file import read_axle
    assert read_axle(str(toml)).params == apply_tyre(paper_axle(), read_tir(str(EXAMPLE_TIR))).params
    code, out, _ = run("params", "--tyre", EXAMPLE_TIR, "--json")
    tyre = json.loads(out)["tyre"]
    assert tyre["fittyp"] == 61 and "[LATERAL_COEFFICIENTS] PEY3" in tyre["unused"]
    # --set goes on top of the tyre
    code, out, _ = run("params", "--tyre", EXAMPLE_TIR, "--set", "p_ky1=14", "--json")
    assert {r["name"]: r["value"] for r in json.loads(out)["parameters"]}["p_ky1"] == 14.0
    assert dataclasses.is_dataclass(read_tir(str(EXAMPLE_TIR)))
