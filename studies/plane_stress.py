"""Inextensible-director SVK vs the plane-stress (condensed) law, on the paper scene and a nu sweep.

With the director inextensible the thickness strain vanishes, and the hoop/axial
stiffness of 3-D St Venant-Kirchhoff is lambda + 2 mu, which grows without bound as
nu -> 0.5 (locking): the fastest mode at t = 0 becomes the grid-scale axial wave, of frequency
about (2/ds) sqrt((lambda + 2 mu)/rho). Condensing the thickness stress out gives E / (1 - nu^2),
and the fastest mode stays the transverse-shear mode, about sqrt(3 mu / rho) / h. The laws also
give different equilibrium radii R(gamma): 1 - R is proportional to (lambda/2 + 2 mu)/(lambda + 2 mu)
with the law's lambda (thin limit). Each case runs the paper scene to t = 0.143 s with leap-frog
at the largest step <= min(dt, half the bound) that divides 1 ms.
Writes OUT/plane_stress.nc and OUT/plane_stress.png; prints a markdown table. ``main`` returns
the netCDF's Dataset.
Usage: python studies/plane_stress.py [--dt 1e-5] [--quick] [--out out]
(--quick: nu = 0.499, 0.4999 only; about 10 s.)
"""

import os

import numpy as np
import xarray as xr

import mol_shell
from mol_shell.cli.args import number_arg
from mol_shell.cli.scripts import output_folder, run_script, script_parser, simulate
from mol_shell.model.equilibrium import spectrum_bounds
from mol_shell.results.cf import described
from mol_shell.runs.simulate import build, resolve

TIMES = [0.0, 0.02, 0.07, 0.106, 0.143]
NUS = (0.3, 0.45, 0.49, 0.499, 0.4999)
QUICK_NUS = (0.499, 0.4999)
MATERIALS = ("svk", "svk-plane-stress")
#: units and long_name of every variable of OUT/plane_stress.nc
MEANINGS = {
    "material": (None, "material law"), "nu": ("1", "Poisson's ratio"), "s": ("m", "arc length"),
    "R": ("m", "equilibrium radius R(gamma)"), "omega_max": ("s-1", "largest |eigenvalue| of the Jacobian at t = 0"),
    "dt": ("s", "leap-frog step"), "r_min": ("m", "smallest radius at the saved times"),
    "r_max": ("m", "largest radius at the saved times"), "theta_max": ("rad", "largest |theta| at the saved times"),
    "chi_at_end_max": ("rad", "largest |chi| at t = 0.143 s"), "psi_max": ("rad", "largest |psi| at the saved times"),
    "r_final": ("m", "radius at t = 0.143 s"),
}


def measure(nu, material, dt):
    scene = resolve(mol_shell.TwistedCylinder(nu=nu, material=material))
    system, _ = build(scene, 40)
    top = spectrum_bounds(system.jac, system.initial_state(scene), False)[0]
    step = min(dt, 0.5 / top)
    step = 1e-3 / np.ceil(1e-3 / step)  # divides the saved times (multiples of 1 ms)
    ds = simulate(scene, times=TIMES, dt=step, progress=False)
    return {
        "R": scene.R,
        "omega_max": top,
        "dt": step,
        "r_min": float(ds.r.min()),
        "r_max": float(ds.r.max()),
        "theta_max": float(abs(ds.theta).max()),
        "chi_at_end_max": float(abs(ds.chi.isel(time=-1)).max()),
        "psi_max": float(abs(ds.psi).max()),
    }, ds


def summary(rows, finals, nus, dt):
    """The Dataset of OUT/plane_stress.nc: ``rows[material, nu]`` (measure's numbers) and ``finals[material, nu]``
    (the radius at the last time, along s)."""
    keys = list(next(iter(rows.values())))
    data = {k: (("material", "nu"), [[rows[m, nu][k] for nu in nus] for m in MATERIALS]) for k in keys}
    data["r_final"] = (("material", "nu", "s"), [[np.asarray(finals[m, nu]) for nu in nus] for m in MATERIALS])
    s = np.asarray(finals[MATERIALS[0], nus[0]].s)
    out = xr.Dataset(data, coords={"material": list(MATERIALS), "nu": list(nus), "s": s})
    return described(out, "mol_shell: inextensible-director SVK against the plane-stress law", MEANINGS,
                     dt_max=dt, units_dt_max="s", saved_times=", ".join(map(str, TIMES)), units_saved_times="s")


def main(argv=None):
    parser = script_parser(__doc__)
    parser.add_argument("--dt", type=number_arg("--dt", unit="s"), default=1e-5, help="largest leap-frog step, s (default 1e-5)")
    parser.add_argument("--quick", action="store_true", help=f"nu = {', '.join(map(str, QUICK_NUS))} only")
    parser.add_argument("--out", default="out", help="output directory (default: out)")
    args = parser.parse_args(argv)
    nus = QUICK_NUS if args.quick else NUS
    output_folder(args.out)
    rows, finals = {}, {}
    for material in MATERIALS:
        for nu in nus:
            rows[material, nu], ds = measure(nu, material, args.dt)
            finals[material, nu] = ds.r.isel(time=-1)
    out = summary(rows, finals, nus, args.dt)
    mol_shell.write_netcdf(out, os.path.join(args.out, "plane_stress.nc"))
    print("| material | nu | R [m] | max abs(eig) [1/s] | r range at the paper's times [m] | max abs(theta) "
          "| max abs(psi) |")
    print("|---|---|---|---|---|---|---|")
    for (m, nu), row in rows.items():
        print(f"| {m} | {nu:g} | {row['R']:.6f} | {row['omega_max']:.4g} | {row['r_min']:.5f} .. {row['r_max']:.5f} "
              f"| {row['theta_max']:.4f} | {row['psi_max']:.2e} |")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6))
    shown = 0.49 if 0.49 in nus else nus[0]  # the paper's nu
    for m, style in zip(MATERIALS, ("o-", "s--")):
        axes[0].semilogx([0.5 - nu for nu in nus], [rows[m, nu]["omega_max"] for nu in nus], style, label=m)
        axes[1].plot(out.s, out.r_final.sel(material=m, nu=shown), style, ms=3, label=f"{m}, nu = {shown:g}")
    axes[0].set_xlabel("0.5 - nu")
    axes[0].set_ylabel("max |eig J| at t = 0 [1/s]")
    axes[0].legend(fontsize=8)
    axes[1].set_xlabel("s [m]")
    axes[1].set_ylabel("r at t = 0.143 s [m]")
    axes[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "plane_stress.png"), dpi=110)
    plt.close(fig)
    print(f"wrote {args.out}/plane_stress.nc, {args.out}/plane_stress.png")
    return out


if __name__ == "__main__":
    run_script(main)
