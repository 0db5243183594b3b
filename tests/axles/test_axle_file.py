"""Axle files: write, read, round trip to identical numbers, every kind of bad file, --set in interface units."""

import json
import math

import pytest

from axles.axle import AxleData, entries, paper_axle
from axles.axle_file import AxleFileError, format_axle, parse_axle, read_axle
from comparisons.cli.main import main
from axles.dimensions import DEFAULT_DIMENSIONS
from axles.parameters import YANG2024


@pytest.fixture
def run(capsys):
    """The command in this process (the error path is the same as from the shell; a subprocess costs 1 s)."""
    def call(*args):
        code = main(list(args))
        out, err = capsys.readouterr()
        return code, out, err
    return call


@pytest.fixture(scope="module")
def paper_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("axle") / "paper.toml"
    assert main(["params", "--write", str(path)]) == 0
    return path


def test_write_says_what_it_wrote_and_names_the_axle_after_the_file(run, tmp_path):
    path = tmp_path / "my truck.toml"
    code, out, err = run("params", "--write", str(path), "--set", "gamma=3")
    assert code == 0 and err == ""
    lines = out.splitlines()
    assert len(lines) == 2   # what was written, and what to do with it; not the 80-line table
    assert lines[0].startswith(f"wrote {path}: axle file name = \"my truck\", {len(entries())} entries")
    assert "differs from the paper in gamma = 3 deg" in lines[0]
    axle = read_axle(str(path))
    assert axle.name == "my truck" and axle.differences()[0]["name"] == "gamma"


def test_written_paper_axle_reads_back_bit_for_bit(paper_file):
    axle = read_axle(str(paper_file))
    assert axle.params == YANG2024 and axle.dims == DEFAULT_DIMENSIONS
    assert axle.name == "paper"     # named after the file: the user's axle from now on
    assert axle.is_paper and axle.differences() == [] and axle.inherited == ()
    assert len(axle.sha256) == 64 and axle.file == str(paper_file)
    text = paper_file.read_text()
    # every entry with its unit and source beside it; angles in degrees, pressures in bar
    for name, e in entries().items():
        assert any(line.startswith(f"{name} = ") and f"# {e.unit} |" in line for line in text.splitlines()), name
    assert "gamma = 2.29183118052329" in text and "pi0 = 2.5 " in text
    # the elements' dimensions carry their neutral value and, where they are not estimates, their source
    line = next(x for x in text.splitlines() if x.startswith("camber_p_ky6 = "))
    assert "neutral 0" in line and "Pacejka" in line and "# 1/rad |" in line
    assert entries()["axle_roll_steer"].neutral_si == 0.0 and entries()["wheel_mass"].neutral_si is None


def test_round_trip_of_awkward_values_is_exact():
    """Degrees and bar are converted back to SI exactly for any value (not just the paper's)."""
    axle = paper_axle().with_values({"gamma": 0.0123456789012345, "pi0": 2.3456789e5, "wheel_mass": 41.123456789})
    again = parse_axle(format_axle(axle))
    assert again.params == axle.params and again.dims == axle.dims


def test_hopf_of_paper_file_equals_built_in(paper_file, capsys):
    assert main(["hopf", "--pressure", "1.5", "--json"]) == 0
    built_in = json.loads(capsys.readouterr().out)
    assert main(["hopf", "--pressure", "1.5", "--axle", str(paper_file), "--json"]) == 0
    from_file = json.loads(capsys.readouterr().out)
    assert from_file["hopf"] == built_in["hopf"]
    assert from_file["axle"]["file"] == str(paper_file) and from_file["axle"]["differs_from_paper"] == []
    assert from_file["pressure_bar"] == from_file["pressure_left_bar"] == from_file["pressure_right_bar"] == 1.5


def test_edited_file_and_set_on_top(tmp_path, capsys):
    path = tmp_path / "edited.toml"
    path.write_text('name = "stiff tie-rod"\nbase = "YANG2024"\n[table1]\nk1 = 50000.0\ngamma = 3.0\n')
    assert main(["hopf", "--pressure", "2.5", "--axle", str(path), "--set", "t0=0.08", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    diff = {d["name"]: d for d in out["axle"]["differs_from_paper"]}
    assert set(diff) == {"k1", "gamma", "t0"}
    assert diff["gamma"]["value"] == pytest.approx(3.0) and diff["gamma"]["unit"] == "deg"
    assert diff["gamma"]["paper"] == pytest.approx(math.degrees(0.04))
    assert "operating.pressure_range_bar" in out["axle"]["inherited"] and "I1" in out["axle"]["inherited"]
    assert out["axle"]["overrides"] == {"t0": 0.08}
    # the same axle through --set only gives the same numbers
    assert main(["hopf", "--pressure", "2.5", "--set", "k1=50000", "--set", "gamma=3", "--set", "t0=0.08",
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["hopf"] == out["hopf"]


def test_set_takes_degrees_for_angles(capsys):
    assert main(["params", "--set", "gamma=2.291831180523293", "--json"]) == 0
    rows = {r["name"]: r for r in json.loads(capsys.readouterr().out)["parameters"]}
    assert rows["gamma"]["unit"] == "deg" and rows["gamma"]["value"] == pytest.approx(math.degrees(0.04))
    assert rows["pi0"]["unit"] == "bar" and rows["pi0"]["range"] == [0.1, 20.0]
    assert rows["wheel_mass"]["section"] == "multibody" and rows["wheel_mass"]["plausible"] == [30.0, 60.0]


BAD = [
    ("syntax", 'name = "x"\n[table1\nI1 = 3\n', "TOML syntax error", "line 2"),
    ("unknown key", 'name = "x"\nbase = "YANG2024"\n[table1]\nI_1 = 3.0\n', "unknown entry 'I_1'", "did you mean 'I1'"),
    ("wrong section", 'name = "x"\nbase = "YANG2024"\n[table1]\nwheel_mass = 3.0\n', "unknown entry 'wheel_mass'",
     "belongs in [multibody]"),
    ("top-level entry", 'name = "x"\nbase = "YANG2024"\nk1 = 3.0\n', "unknown key 'k1'", "belongs in [table1]"),
    ("missing", 'name = "x"\n[table1]\nI1 = 6.0\n', "missing entry 'I2'", "base = \"YANG2024\""),
    ("wrong type", 'name = "x"\nbase = "YANG2024"\n[table1]\nI1 = "6"\n', "must be a number", "I1"),
    ("boolean", 'name = "x"\nbase = "YANG2024"\n[multibody]\nwheel_mass = true\n', "must be a number", "wheel_mass"),
    ("out of range", 'name = "x"\nbase = "YANG2024"\n[table1]\ngamma = 60.0\n', "outside its physical range",
     "[-20, 20] deg"),
    ("huge", 'name = "x"\nbase = "YANG2024"\n[table1]\nI1 = 1e308\n', "outside its physical range", "kg m^2"),
    ("no name", 'base = "YANG2024"\n', "'name' must be a non-empty string", ""),
    ("bad base", 'name = "x"\nbase = "TRUCK9"\n', "base must be one of", "YANG2024"),
    ("bad range", 'name = "x"\nbase = "YANG2024"\n[operating]\npressure_range_bar = [3.0, 1.0]\n', "LO <= HI", ""),
    ("bad plausible", 'name = "x"\nbase = "YANG2024"\n[plausible]\nwheel_mass = [30.0]\n', "two numbers", ""),
]


@pytest.mark.parametrize("case, text, fragment, detail", BAD, ids=[b[0] for b in BAD])
def test_bad_file_is_one_line_exit_2(tmp_path, run, case, text, fragment, detail):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(AxleFileError) as err:
        read_axle(str(path))
    assert fragment in str(err.value) and detail in str(err.value) and str(path) in str(err.value)
    code, out, stderr = run("hopf", "--pressure", "1.5", "--axle", str(path))
    assert code == 2 and len(stderr.strip().splitlines()) == 1 and fragment in stderr and "Traceback" not in stderr


def test_unreadable_files(tmp_path, run):
    code, _, err = run("hopf", "--pressure", "1.5", "--axle", str(tmp_path / "nope.toml"))
    assert code == 2 and "cannot read the axle file" in err and len(err.strip().splitlines()) == 1
    code, _, err = run("hopf", "--pressure", "1.5", "--axle", str(tmp_path))
    assert code == 2 and "directory" in err
    binary = tmp_path / "bin.toml"
    binary.write_bytes(b"\xff\xfe\x00name")
    code, _, err = run("hopf", "--pressure", "1.5", "--axle", str(binary))
    assert code == 2 and len(err.strip().splitlines()) == 1


def test_axle_describe_lists_differences_in_interface_units():
    axle = AxleData().with_overrides({"gamma": 3.0, "wheel_mass": 45.0})
    diff = {d["name"]: d for d in axle.describe()["differs_from_paper"]}
    assert diff["gamma"]["unit"] == "deg" and diff["wheel_mass"]["value"] == 45.0
    assert "gamma = 3 deg" in axle.label()


@pytest.mark.parametrize("args", [
    ["hopf", "--pressure", "2.5", "--model", "mbs", "--fidelity", "full"],
    ["cycles", "--pressure", "2.5"],
    ["curves", "--param", "t0", "--range", "0.06", "0.08", "--pressure", "2.5", "--vmax", "120"],
    ["simulate", "--pressure", "1.5", "--speed", "60", "--duration", "2"],
    ["simulate", "--model", "mbs", "--pressure", "1.5", "--speed", "60", "--duration", "1"],
    ["assumptions", "--pressure", "2.5", "--no-cycles"],
], ids=["hopf-mbs", "cycles", "curves", "simulate", "simulate-mbs", "assumptions"])
def test_paper_file_gives_todays_numbers_in_every_command(paper_file, capsys, args):
    assert main(args + ["--json"]) in (0, 3)
    built_in = json.loads(capsys.readouterr().out)
    assert main(args + ["--axle", str(paper_file), "--json"]) in (0, 3)
    from_file = json.loads(capsys.readouterr().out)
    assert from_file.pop("axle")["file"] == str(paper_file) and built_in.pop("axle")["file"] is None
    assert from_file == built_in
