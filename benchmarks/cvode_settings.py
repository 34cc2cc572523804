"""Benchmark: how often CVODE-BDF and IDA refresh their Jacobian and factorise, measured on several motions.

SUNDIALS evaluates a Jacobian at least every ``msbj`` steps (``jac_every``; 0: 51) and factorises the Newton matrix
at least every ``msbp`` steps (``setup_every``; 0: 20) and whenever ``gamma = h beta`` moves by 30 %; on a failed
Newton iteration with an old Jacobian it takes a fresh one and tries again. Longer reuse saves Jacobians and
factorisations, and costs Newton iterations where the motion changes the Jacobian. This script runs each setting
on each scene at ``rtol = 1e-6`` (``{}``: the defaults; ``jac_every = setup_every = 0``: SUNDIALS' own; the fastest of ``--repeats`` runs of the integration's own ``wall_time_s``, the
kernels compiled beforehand) and reports wall time, steps, Newton iterations, Jacobians, set-ups and the error
against the same integrator at ``rtol = 1e-10`` with its defaults (largest over r, theta, chi of
max |u - u_ref| / max |u_ref| at the final time). Public tools only: ``mol_shell.simulate``.

Usage: python benchmarks/cvode_settings.py [--repeats 3] [--scenes paper viscous ...] [--json out.json]
"""

import json
import warnings

import numpy as np
from arguments import Parser, integer  # benchmarks/ is this script's folder

import mol_shell
from mol_shell.runs.simulate import resolve

SCENES = {  # name: (scene, n, t_end)
    "paper": (lambda: mol_shell.TwistedCylinder(), 40, 0.143),
    "viscous": (lambda: mol_shell.TwistedCylinder(eta_mu=100, eta_lambda=200), 640, 0.01),
    "viscous-2560": (lambda: mol_shell.TwistedCylinder(eta_mu=100, eta_lambda=200), 2560, 0.01),
    "driven-twist": (lambda: mol_shell.TwistedCylinder(end_omega=10.0, eta_mu=5, eta_lambda=10), 160, 0.05),
    "sphere-breathing": (lambda: mol_shell.Sphere(R=1.05, eta_mu=20, eta_lambda=40), 160, 0.011),
    "rubber-breathing": (lambda: mol_shell.Sphere(material="neo-hookean-incompressible", E=3e6, h=0.01, R=1.3,
                                                  eta_mu=10, eta_lambda=0), 120, 0.03),
}
SETTINGS = {
    "cvode-bdf": [{"jac_every": 0, "setup_every": 0}, {"jac_every": 0, "setup_every": 50},
                  {"jac_every": 200, "setup_every": 100}],
    "ida": [{}, {"jac_reuse": 10}, {"jac_reuse": 1000}],
}


def fields(ds):
    return {v: ds[v].values[-1] for v in ("r", "theta", "chi")}


def error(ds, ref):
    a, b = fields(ds), fields(ref)
    return max(float(np.max(np.abs(a[v] - b[v])) / max(np.max(np.abs(b[v])), 1e-300)) for v in a)


def main():
    parser = Parser(__doc__)  # a value out of its range: one line naming the option, exit code 2
    parser.add_argument("--repeats", type=integer("--repeats", 1), default=3,
                        help="runs of each setting; the fastest is reported (an integer >= 1, default: 3)")
    parser.add_argument("--scenes", nargs="+", default=list(SCENES), choices=list(SCENES), metavar="SCENE",
                        help=f"scenes to run, any of: {', '.join(SCENES)} (default: all)")
    parser.add_argument("--integrators", nargs="+", default=list(SETTINGS), choices=list(SETTINGS),
                        metavar="INTEGRATOR", help=f"integrators to run, any of: {', '.join(SETTINGS)} (default: both)")
    parser.add_argument("--json", default=None, metavar="PATH",
                        help="also write the rows to this JSON file (default: none, the table only)")
    args = parser.parse_args()
    warnings.simplefilter("ignore")  # the scenes' law warnings: known, not measured here
    rows = []
    print("| scene | n | integrator | options | wall [s] | error | steps | Newton | Jacobians | set-ups | status |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name in args.scenes:
        make, n, t_end = SCENES[name]
        scene = resolve(make())
        for integrator in args.integrators:
            ref = mol_shell.simulate(scene, integrator, n=n, times=[0.0, t_end], progress=False, rtol=1e-10,
                                     atol=1e-13)
            for options in SETTINGS[integrator]:
                runs = [mol_shell.simulate(scene, integrator, n=n, times=[0.0, t_end], progress=False, rtol=1e-6,
                                           atol=1e-9, **options) for _ in range(args.repeats)]
                ds = min(runs, key=lambda d: float(d.attrs["wall_time_s"]))
                a = ds.attrs
                row = dict(scene=name, n=n, integrator=integrator, options=options, wall_s=float(a["wall_time_s"]),
                           error=error(ds, ref), steps=int(a["n_steps"]), newton=int(a["n_newton"]),
                           jacobians=int(a["n_jac"]), setups=int(a.get("n_setups", -1)), status=str(a["status"]))
                rows.append(row)
                print(f"| {name} | {n} | {integrator} | {options or 'defaults'} | {row['wall_s']:.4f} | "
                      f"{row['error']:.1e} | {row['steps']} | {row['newton']} | {row['jacobians']} | {row['setups']} | "
                      f"{row['status']} |", flush=True)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1)


if __name__ == "__main__":
    main()
