"""What each view reads of a run, and a damaged run file refused in one line naming the file and what it lacks (exit 2;
a KeyError, an AttributeError said "internal error", exit 1); a shell on its axis (r = 0, finite) animated."""

import warnings

import numpy as np
import pytest
from PIL import Image

import mol_shell
import mol_shell.views.fields as fields_module
from mol_shell import ParameterError
from mol_shell.cli.main import main
from mol_shell.views.animate import _extents, animate
from mol_shell.views.export import export
from mol_shell.views.fibres import plot_fibres
from mol_shell.views.history import plot_history
from mol_shell.views.plotting import plot_meridian, plot_snapshots

SHELL = ("z", "r", "chi", "theta", "psi")  # the revolved shell: z k + r a2(phi + chi), offset along d(theta, psi)
FACES = ("zeta1_used", "h")  # a uniform wall's faces: zeta1 and zeta1 + 2h
#: view -> (call, the variables and attributes it reads, read from the code by hand)
VIEWS = {
    "export": (lambda ds, out: export(ds, out / "x.pvd", n_phi=3), SHELL, ()),
    "export --faces": (lambda ds, out: export(ds, out / "x.xdmf", n_phi=3, faces=True), SHELL, FACES),
    "animate": (lambda ds, out: animate(ds, out / "a.gif", n_phi=3, fibres=1, width=100, progress=False), SHELL, ()),
    "plot": (lambda ds, out: plot_snapshots(ds, out / "p.png"), ("r", "theta", "chi"), ()),
    "plot (meridian)": (lambda ds, out: plot_meridian(ds, out / "m.png", max_times=2),
                        ("r", "z", "chi", "psi", "energy", "r0", "z0"), ()),
    "plot --figure history": (lambda ds, out: plot_history(ds, out / "h.png"), ("r", "energy"), ()),
    "plot --figure fibres": (lambda ds, out: plot_fibres(ds, out / "f.png", count=2), ("r", "chi", "theta", "psi"),
                             FACES),
}
REFERENCE = ("z0", "r0", "theta0")  # the reference meridian: a run file holds all of it or none
RUN = ("r", "theta", "chi")  # a Dataset without one of them is not a run (mol_shell.results.dataset.is_run)


@pytest.fixture(scope="module")
def run():
    """The paper's scene on 8 nodes over 20 us (2 saved times), without stresses."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return mol_shell.simulate(mol_shell.TwistedCylinder(), n=8, times=[0, 2e-5], progress=False, stresses=False)


@pytest.mark.parametrize("view", VIEWS)
def test_each_view_draws_a_run_of_what_it_reads_and_refuses_one_without_any_of_it(run, view, tmp_path, monkeypatch):
    call, variables, attributes = VIEWS[view]
    kept = list(dict.fromkeys(RUN + variables + (REFERENCE if set(variables) & set(REFERENCE) else ())))
    least = run[kept]
    least.attrs = {name: run.attrs[name] for name in attributes}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        call(least, tmp_path)  # what it reads is enough
    for name in variables + attributes:
        damaged = run.drop_vars(name) if name in variables else run.copy()
        damaged.attrs.pop(name, None)
        with pytest.raises(ParameterError) as refused:
            call(damaged, tmp_path)
        kind = "variable" if name in variables else "attribute"
        said = ("not one run" if name in RUN else f"has no variable {name}, a part of the reference meridian"
                if name in REFERENCE else f"has no {kind} {name}, which {view.split(' (')[0]} reads")
        assert said in str(refused.value), str(refused.value)
    # and each of them is read: without the refusal, the view fails where it reads it
    monkeypatch.setattr(fields_module, "_check_holds", lambda *args: None)
    for name in [name for name in variables + attributes if name not in RUN]:
        damaged = run.drop_vars(name) if name in variables else run.copy()
        damaged.attrs.pop(name, None)
        with pytest.raises((KeyError, AttributeError)):
            call(damaged, tmp_path)


def test_the_command_line_refuses_a_damaged_run_file_in_one_line_naming_it(run, tmp_path, capsys):
    damaged = {"m_psi.nc": run.drop_vars("psi"), "m_th0.nc": run.drop_vars("theta0"), "m_noz.nc": run.copy()}
    damaged["m_noz.nc"].attrs.pop("zeta1_used")
    for name, ds in damaged.items():
        mol_shell.write_netcdf(ds, tmp_path / name)
    cases = [(["export", "m_psi.nc", "-o", "q.xdmf"], "FILE = 'm_psi.nc' has no variable psi, which export reads"),
             (["animate", "m_psi.nc", "-o", "q.gif"], "FILE = 'm_psi.nc' has no variable psi, which animate reads"),
             (["plot", "m_th0.nc", "-o", "q.png"], ("FILE = 'm_th0.nc' has no variable theta0, a part of the reference "
                                                     "meridian")),
             (["export", "m_noz.nc", "--faces", "-o", "q.xdmf"],
              "FILE = 'm_noz.nc' has no attribute zeta1_used, which export --faces reads")]
    with pytest.MonkeyPatch.context() as patch:
        patch.chdir(tmp_path)
        for argv, start in cases:
            assert main(argv) == 2, argv
            err = capsys.readouterr().err
            assert err.startswith(f"mol-shell: error: {start}") and len(err.splitlines()) == 1, err
    assert sorted(f.name for f in tmp_path.iterdir()) == sorted(damaged)


def test_a_shell_on_its_axis_is_animated_in_a_box_of_its_height(run, tmp_path):
    on_axis = run.copy(deep=True)
    on_axis["r"].values[:] = 0.0
    z = on_axis["z"].values
    extent, zlo, zhi = _extents(on_axis, 3)
    # every point on the axis: the box as high as the shell, its half-width 5 % of that (and 2 % over)
    assert (zlo, zhi) == (z.min(), z.max()) and extent == pytest.approx(0.05 * 1.02 * (z.max() - z.min()))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # matplotlib's "identical low and high xlims", then a singular matrix
        assert animate(on_axis, tmp_path / "a.gif", n_phi=3, fibres=1, width=100, progress=False) == 2
    assert Image.open(tmp_path / "a.gif").n_frames == 2 and np.ptp(z) > 0
