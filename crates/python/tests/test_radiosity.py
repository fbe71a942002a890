"""form_factor and radiosity against the `irradia formfactor` / `irradia radiosity` commands."""

import csv

import numpy as np
import pytest

import irradia


def test_form_factor_equals_cli(cli):
    for case in irradia.form_factor_cases():
        params = {p: 1.0 for p in case["params"]}
        args = [x for p in params for x in ("--" + p, "1")]
        r = cli("formfactor", case["name"], *args, check=False)
        if r.returncode != 0:
            with pytest.raises(irradia.IrradiaError) as e:
                irradia.form_factor(case["name"], **params)
            assert str(e.value) in r.stderr
            continue
        assert "%.10f" % irradia.form_factor(case["name"], **params) == r.stdout.strip()


def test_form_factor_values_and_errors(cli):
    assert irradia.form_factor("element-coaxial-disk", h=1, r=1) == pytest.approx(0.5, abs=1e-12)
    with pytest.raises(irradia.IrradiaError) as e:
        irradia.form_factor("no-such-case", h=1)
    r = cli("formfactor", "no-such-case", "--h", "1", check=False)
    assert r.returncode == 2 and str(e.value) in r.stderr
    with pytest.raises(irradia.IrradiaError) as e:
        irradia.form_factor("element-coaxial-disk", h=1)
    r = cli("formfactor", "element-coaxial-disk", "--h", "1", check=False)
    assert str(e.value) in r.stderr


def test_radiosity_solve_and_residuals_equal_cli(tmp_path, cli):
    conv = tmp_path / "c.csv"
    cli("radiosity", "--elements", "200", "--solver", "jacobi", "--form-factors", "contour",
        "--convergence", conv, "-o", tmp_path / "r.png", "--width", "16", "--height", "16", "--quiet")
    r = irradia.radiosity(elements=200, solver="jacobi", form_factors="contour",
                          compare_solvers=True)
    n = r["radiosity"].shape[0]
    assert r["radiosity"].shape == (n, 3) and r["area"].shape == (n,)
    ref = {}
    with open(conv) as f:
        for row in list(csv.reader(f))[1:]:  # solver,iteration,residual ({:e}: round trip)
            ref.setdefault(row[0], []).append(float(row[2]))
    assert set(ref) == set(r["histories"])
    for name, hist in r["histories"].items():
        assert np.array_equal(hist, np.array(ref[name])), name
    assert np.array_equal(r["residuals"], r["histories"]["jacobi"])
    assert r["residual"] <= 1e-6


def test_form_factor_matrix_of_a_closed_room():
    r = irradia.radiosity(builtin="furnace", elements=150, form_factors="contour",
                          solver="direct", return_form_factors=True)
    f, area = r["form_factors"], r["area"]
    n = area.size
    assert f.shape == (n, n)
    # Every row of a closed room sums to one, and A_i F_ij = A_j F_ji.
    assert abs(np.average(f.sum(1), weights=area) - 1) < 0.02
    af = area[:, None] * f
    assert np.abs(af - af.T).max() < 0.05 * area.max()
    assert "form_factors" not in irradia.radiosity(builtin="furnace", elements=50)


def test_radiosity_scene_object_and_errors():
    s = irradia.builtin("cornell")
    r = irradia.radiosity(s, elements=100, solver="southwell")
    assert r["radiosity"].shape[1] == 3 and r["residuals"].size > 0
    assert (r["radiosity"] >= 0).all()
    with pytest.raises(irradia.IrradiaError, match="--rays must be at least 1"):
        irradia.radiosity(rays=0)
    with pytest.raises(irradia.IrradiaError, match="unknown solver"):
        irradia.radiosity(solver="cg")
    with pytest.raises(irradia.IrradiaError, match="unknown built-in"):
        irradia.radiosity(builtin="nothing")
    with pytest.raises(irradia.IrradiaError, match="not both"):
        irradia.radiosity(s, builtin="cornell")
