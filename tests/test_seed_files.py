"""The seed's file formats (report sections 3.1-3.2): exact round trips, and bad input
refused with a message naming the file, the line and the value - with nothing written."""

import numpy as np
import pytest

from taisph.cli import main as cli
from taisph.formats import dat as seedio

GOOD = "2\n0 0.1 0.2 0 0 0.4 1000 0 0\n1 0.3 0.2 0 0 0.4 1000 0 0\n"

# (name, file content, line named in the message, text the message must contain)
BAD = [
    ("empty", "", None, "empty"),
    ("blank", "\n  \n", None, "empty"),
    ("count not a number", "two\n0 0.1 0.2 0 0 0.4 1000 0 0\n", 1, "'two'"),
    ("count line missing", "0 0.1 0.2 0 0 0.4 1000 0 0\n", 1, "count line missing"),
    ("count too large", "3\n0 0.1 0.2 0 0 0.4 1000 0 0\n1 0.3 0.2 0 0 0.4 1000 0 0\n", 3, "announces 3"),
    ("count too small", "1\n0 0.1 0.2 0 0 0.4 1000 0 0\n1 0.3 0.2 0 0 0.4 1000 0 0\n", 3, "extra particle line"),
    ("zero particles", "0\n", 1, "count is 0"),
    ("missing column", "2\n0 0.1 0.2 0 0 0.4 1000 0 0\n1 0.3 0.2 0 0 0.4 1000 0\n", 3, "missing columns"),
    ("extra column", "2\n0 0.1 0.2 0 0 0.4 1000 0 0\n1 0.3 0.2 0 0 0.4 1000 0 0 7\n", 3, "extra columns"),
    ("no dimension has 10 columns", "1\n0 0.1 0.2 0 0 0.4 1000 0 0 7\n", 2, "found 10 columns"),
    ("not a number", "2\n0 0.1 0.2 0 0 0.4 1000 0 0\n1 0.3 0.2 zero 0 0.4 1000 0 0\n", 3, "'zero'"),
    ("nan", "2\n0 0.1 0.2 0 0 0.4 1000 0 0\n1 0.3 nan 0 0 0.4 1000 0 0\n", 3, "'nan'"),
    ("infinite", "2\n0 0.1 0.2 0 0 0.4 1000 0 0\n1 0.3 0.2 0 -inf 0.4 1000 0 0\n", 3, "'-inf'"),
    ("zero mass", "2\n0 0.1 0.2 0 0 0 1000 0 0\n1 0.3 0.2 0 0 0.4 1000 0 0\n", 2, "(mass) is 0"),
    ("negative mass", "2\n0 0.1 0.2 0 0 0.4 1000 0 0\n1 0.3 0.2 0 0 -0.4 1000 0 0\n", 3, "(mass) is -0.4"),
    ("zero density", "2\n0 0.1 0.2 0 0 0.4 1000 0 0\n1 0.3 0.2 0 0 0.4 0 0 0\n", 3, "(density) is 0"),
    ("duplicate index", "2\n1 0.1 0.2 0 0 0.4 1000 0 0\n1 0.3 0.2 0 0 0.4 1000 0 0\n", 3, "index 1 is used twice"),
    ("index out of range", "2\n0 0.1 0.2 0 0 0.4 1000 0 0\n2 0.3 0.2 0 0 0.4 1000 0 0\n", 3, "index 2 is out of range"),
    ("negative index", "2\n0 0.1 0.2 0 0 0.4 1000 0 0\n-1 0.3 0.2 0 0 0.4 1000 0 0\n", 3, "index -1"),
    ("fractional index", "2\n0 0.1 0.2 0 0 0.4 1000 0 0\n0.5 0.3 0.2 0 0 0.4 1000 0 0\n", 3, "'0.5'"),
    ("density far from rho0", "2\n0 0.1 0.2 0 0 0.4 1000 0 0\n1 0.3 0.2 0 0 0.4 800 0 0\n", 3, "density 800"),
]


def test_round_trip_2d_and_3d(tmp_path, rng):
    """Written files read back bit for bit (17 significant digits), in index order."""
    for dim in (2, 3):
        n = 50
        x, v = rng.normal(size=(n, dim)), rng.normal(size=(n, dim))
        m, rho, p, e = rng.uniform(0.1, 1, n), rng.uniform(900, 1100, n), rng.normal(size=n), rng.normal(size=n)
        path = seedio.write_particles(tmp_path / f"p{dim}.dat", x, v, m, rho, p, e)
        lines = path.read_text().splitlines()
        assert lines[0] == str(n) and len(lines[1].split()) == {2: 9, 3: 11}[dim]
        d = seedio.read_particles(path)
        assert d.dim == dim
        for got, want in ((d.position, x), (d.velocity, v), (d.mass, m), (d.density, rho), (d.pressure, p),
                          (d.energy, e)):
            np.testing.assert_array_equal(got, want)


def test_indices_in_any_order(tmp_path):
    """Particles may be listed in any index order; they are returned sorted by index."""
    path = tmp_path / "p.dat"
    path.write_text("3\n2 2 0 0 0 1 1000 0 0\n\n0 0 0 0 0 1 1000 0 0\n1 1 0 0 0 1 1000 0 0\n")
    d = seedio.read_particles(path)
    np.testing.assert_array_equal(d.position[:, 0], [0, 1, 2])
    np.testing.assert_array_equal(d.line, [4, 5, 2])


@pytest.mark.parametrize("name,text,line,needle", BAD, ids=[b[0] for b in BAD])
def test_bad_particle_file_refused_by_run(tmp_path, capsys, name, text, line, needle):
    """`run` exits with 2, names file, line and value, and creates no output folder."""
    bad = tmp_path / "bad.dat"
    bad.write_text(text)
    out = tmp_path / "out"
    code = cli.main(["run", str(bad), "0.01", "0.001", "pc", "spline", "--out", str(out), "--no-progress"])
    err = capsys.readouterr().err
    assert code == 2
    assert str(bad) in err
    if line is not None:
        assert f"line {line}:" in err
    assert needle in err, err
    assert not out.exists()


def test_bad_boundary_file_refused(tmp_path, capsys):
    init = tmp_path / "init.dat"
    init.write_text(GOOD)
    walls = tmp_path / "walls.dat"
    walls.write_text("2\n0 0 0 0 0 0.4 1000 0 0\n1 0 x 0 0 0.4 1000 0 0\n")
    out = tmp_path / "out"
    assert cli.main(["run", str(init), str(walls), "0.01", "0.001", "pc", "spline", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"{walls}, line 3: column 3 (y) is 'x'" in err
    # a 3D boundary file with a 2D particle file
    walls.write_text("1\n0 0 0 0 0 0 0 0.4 1000 0 0\n")
    assert cli.main(["run", str(init), str(walls), "0.01", "0.001", "pc", "spline", "--out", str(out)]) == 2
    assert "found 11, expected 9 (2D" in capsys.readouterr().err
    assert not out.exists()


def test_missing_file_and_dim_flag(tmp_path, capsys):
    missing = tmp_path / "nope.dat"
    assert cli.main(["run", str(missing), "0.01", "0.001", "pc", "spline"]) == 2
    assert f"{missing}: no such particle file" in capsys.readouterr().err
    init = tmp_path / "init.dat"
    init.write_text(GOOD)
    assert cli.main(["run", str(init), "0.01", "0.001", "pc", "spline", "--dim", "3"]) == 2
    assert "found 9, expected 11 (3D" in capsys.readouterr().err


@pytest.mark.parametrize("args,needle", [
    (["0.01", "0.001", "pc"], "(5 or 6 values), got 4"),
    (["0.01", "0.001", "rk4", "spline"], "INTEGRATOR must be one of"),
    (["0.01", "0.001", "pc", "cubic"], "KERNEL must be one of"),
    (["0.01", "-1", "pc", "spline"], "DT must be a number > 0, got '-1'"),
    (["ten", "0.001", "pc", "spline"], "TFINAL must be a number > 0, got 'ten'"),
    (["0.01", "0.1", "pc", "spline"], "larger than TFINAL"),
    (["0.01", "0.001", "pc", "spline", "--c0", "1,2"], "--c0 has 2 values"),
    (["0.01", "0.001", "pc", "spline", "--gravity=0,-9.81,0"], "--gravity needs 2"),
])
def test_bad_command_line_refused(tmp_path, capsys, args, needle):
    init = tmp_path / "init.dat"
    init.write_text(GOOD)
    out = tmp_path / "out"
    assert cli.main(["run", str(init), *args, "--out", str(out)]) == 2
    assert needle in capsys.readouterr().err
    assert not out.exists()


def test_read_seed_output_without_time(tmp_path):
    """A ``fluid.dat`` with the seed's bare ``[Timestep k]`` headers reads back (time NaN)."""
    path = tmp_path / "fluid.dat"
    path.write_text("[Timestep 1]\n0 0.1 0.2 0 0 0.4 1000 0 0\n1 0.3 0.2 0 0 0.4 1000 0 0\n"
                    "[Timestep 2]\n0 0.1 0.1 0 -1 0.4 1000 0 0\n1 0.3 0.1 0 -1 0.4 1000 0 0\n")
    frames = seedio.read_output(path)
    assert [f.step for f in frames] == [1, 2] and np.isnan(frames[0].time)
    np.testing.assert_array_equal(frames[1].velocity[:, 1], [-1, -1])
