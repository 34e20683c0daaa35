#!/usr/bin/python3
"""Case 4.3 (cases/sandwich_shock_1d.case): the core's plastic compression strain against the impulse
I0 = 2 p_m θ, unsupported and supported, from coupled two-process runs (cases/plot_sandwich_shock.py --sweep).

Checks: each curve rises monotonically with I0; the supported plate's core crushes more than the
unsupported one's at every I0 (the fixed back face cannot take up momentum); the unsupported curve against
an independent estimate (below); and the curves stay at the values pinned below. The pins are this code's
results at 175 water cells (8 mm, degree 1; measured with `cases/plot_sandwich_shock.py --sweep DIR --cells
175`, the values the test measures today); they guard against unintended changes, with a 1 % tolerance,
1.6 times the largest change a finer mesh makes: the same sweep at the case's 350 cells differs from them by
at most 0.61 % (unsupported, 5 MPa), and 2000 cells of degree 2 differ from 350 cells by 0.2 % at 10 MPa
(cases/sandwich_shock_1d.case).

The independent estimate (Fleck and Deshpande, J. Appl. Mech. 71, 2004, stages 1 and 2, with Taylor's
plate): the wet face (m_f = 96 kg/m²) takes Taylor's impulse I_t = I0 ψ^(ψ/(1−ψ)), ψ = ρ_w c_w θ / m_f = 3.85
(Tait water c_w = 1538.4 m/s), and moves off with v0 = I_t / m_f; the core then crushes at its plateau stress
σ_pl = 1.5 MPa until the unsupported sandwich (m_f + m_c + m_b = 197.9 kg/m²) moves as one, dissipating
W = ½ m_f v0² − ½ (m_f v0)² / (m_f + m_c + m_b), so the core strain is W / (σ_pl H_c), H_c = 25 mm. It
leaves out the core's elastic and over-stress share, the water's load after cavitation and the faces'
elasticity; measured against it: −2.6 %, −1.2 %, −7.9 % at p_m = 5, 10, 20 MPa. The run must lie below the
estimate (the over-stress the estimate leaves out resists the crushing, more so at higher crushing rates),
by between 1/1.5 and 1.5 times the measured difference. (The supported plate keeps taking load from the
water after the wet face stops, which stage 2 does not model: no estimate for it.)

    sandwich_shock.py BIN_DIR CASES_DIR WORK_DIR
"""
import csv
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from checks import coupled_steps, requested_times  # noqa: E402

BIN, CASES, WORK = sys.argv[1:4]
END = 2.5e-3  # the sweep's end time; it writes an output every END / 5
PINS = {  # (support, p_m): core strain at 175 cells, the value measured (0.00 % today); re-pinned when the
    # structure's step became each element's present modulus's (issue 17): the lock-up modulus's step had given
    # 0.010524, 0.042715, 0.159220, 0.041548, 0.161828, 0.629600 (0.02-0.07 % more)
    ("unsupported", 5e6): 0.010516,
    ("unsupported", 1e7): 0.042689,
    ("unsupported", 2e7): 0.159133,
    ("supported", 5e6): 0.041537,
    ("supported", 1e7): 0.161772,
    ("supported", 2e7): 0.629457,
}
TOL = 0.01
# Fleck–Deshpande / Taylor estimate of the unsupported core strain (docstring): p_m -> the relative difference
# measured; the bounds are 1.5 times it and 1/1.5 of it.
ESTIMATE_MEASURED = {5e6: -0.0262, 1e7: -0.0118, 2e7: -0.0792}


def fleck_deshpande(p_m):
    """Unsupported core strain from Taylor's impulse on the wet face and momentum sharing through the core."""
    gamma, b, a, rho0, theta = 7.15, 3.31e8, 1e5, 1000.0, 2.4e-4  # the case's water and wave
    z = rho0 * math.sqrt(gamma * (1e5 + b - a) / rho0)
    m_f, m_c, m_b, sigma_pl, h_c = 8000 * 0.012, 236 * 0.025, 8000 * 0.012, 1.5e6, 0.025
    psi = z * theta / m_f
    v0 = 2 * p_m * theta * psi ** (psi / (1 - psi)) / m_f
    w = 0.5 * m_f * v0 ** 2 - 0.5 * (m_f * v0) ** 2 / (m_f + m_c + m_b)
    return w / (sigma_pl * h_c)


script = os.path.join(CASES, "plot_sandwich_shock.py")
r = subprocess.run(["/usr/bin/python3", script, "--sweep", WORK, "--bin", BIN, "--case",
                    os.path.join(CASES, "sandwich_shock_1d.case"), "--p-m", "5e6,1e7,2e7", "--end-time", repr(END),
                    "--cells", "175", "--jobs", "2"])
if r.returncode != 0:
    sys.exit(f"the sweep failed ({r.returncode})")
rows = list(csv.DictReader(open(os.path.join(WORK, "core_strain.csv"))))
strain = {(x["support"], float(x["p_m"])): float(x["core_strain"]) for x in rows}
failures = []
for support in ("unsupported", "supported"):
    curve = [strain[(support, p)] for p in (5e6, 1e7, 2e7)]
    if not all(b > a for a, b in zip(curve, curve[1:])):
        failures.append(f"{support}: the core strain does not rise with the impulse: {curve}")
for p in (5e6, 1e7, 2e7):
    if not strain[("supported", p)] > strain[("unsupported", p)]:
        failures.append(f"p_m {p:g}: the supported core crushes less than the unsupported one")
for p, measured in ESTIMATE_MEASURED.items():
    est = fleck_deshpande(p)
    rel = strain[("unsupported", p)] / est - 1
    lo, hi = 1.5 * measured, measured / 1.5
    print(f"unsupported p_m {p:7.3g}  core strain against Fleck-Deshpande {est:.6f}: {rel:+.2%} (bounds {lo:+.2%} "
          f"to {hi:+.2%}, measured {measured:+.2%})")
    if not lo <= rel <= hi:
        failures.append(f"unsupported p_m {p:g}: core strain {rel:+.2%} from the estimate {est:.6f} (bounds {lo:+.2%} "
                        f"to {hi:+.2%})")
for key, pin in PINS.items():
    got = strain[key]
    rel = abs(got - pin) / pin
    print(f"{key[0]:>11} p_m {key[1]:7.3g}  core strain {got:.6f}  pinned {pin:.6f}  ({rel:.2%})")
    if not rel <= TOL:
        failures.append(f"{key}: core strain {got:.6f} is {rel:.2%} from the pinned {pin:.6f} (tolerance {TOL:.0%})")
# The time-step rule and the output times of every run, from both sides' records (here the structure's step,
# set by the foam's lock-up modulus, limits every step).
for support in ("unsupported", "supported"):
    for p in (5e6, 1e7, 2e7):
        out = os.path.join(WORK, f"{support}_{p:.3g}")
        problems, steps = coupled_steps(out, os.path.join(out, "solid.h5"), END, requested_times(END, END / 5))
        print(f"{support:>11} p_m {p:7.3g}  time steps {'ok' if not problems else 'NO'}: {steps}")
        failures.extend(f"{support} p_m {p:g}: {x}" for x in problems)
if failures:
    print("\n".join(failures))
    sys.exit(1)
print("case 4.3: curves rise with the impulse and match the pinned values")
