#!/usr/bin/python3
"""The steel plate's findings of the paper's application (§5) from a run of cases/undex_steel_plate.case alone
(cases/undex_findings.py needs both plates): the arrival at P1 against the 1D free field, the single peak and
its minimum (times shifted by the steel run's own arrival's lag behind the paper's 0.54 ms), the peak
velocities, the final displacements and PEEQ, the energies' shares, the external work (whole plate).

    undex_steel_findings.py STEEL_DIR FREE_FIELD_DIR
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "cases"))
import undex_findings as U
out, ff = sys.argv[1], sys.argv[2]
print("fluid dx", U.fluid_dx(out))
t, p = U.p_I_at_centre(out, 0)
ta, pk, tpk = U.half_peak_arrival(t, p)
tff, pff, tffpk = U.free_field_arrival(ff)
shift = ta - 0.54e-3
print(f"arrival {ta*1e3:.4f} ms, peak {pk/1e6:.1f} MPa at {tpk*1e3:.4f} ms; free field {tff*1e3:.4f}; diff {(ta-tff)*1e3:+.4f} ms; to paper {shift*1e3:+.3f} ms")
w = (t > tpk) & (t <= 1.1e-3 + shift); iv = np.nonzero(w)[0][np.argmin(p[w])]
w2 = (t > t[iv]) & (t <= 1.6e-3 + shift); ip = np.nonzero(w2)[0][np.argmax(p[w2])]
rise = (p[ip] - p[iv]) / pk
w = (t > tpk) & (t <= 2.0e-3 + shift); imin = np.nonzero(w)[0][np.argmin(p[w])]
print(f"single peak: rise {100*rise:.1f} % of the peak; minimum {p[imin]/1e6:.2f} MPa at {t[imin]*1e3:.3f} ms (shifted {(t[imin]-shift)*1e3:.3f})")
g1, g2 = U.gauge(out, "P1"), U.gauge(out, "P2")
print(f"P1 peak v {g1['v_y'].max():.1f}, P2 peak v {g2['v_y'].max():.1f} m/s; end t {g1['t'][-1]*1e3:.3f} ms: u P1 {g1['u_y'][-1]*1e3:.1f} mm, u P2 {g2['u_y'][-1]*1e3:.1f} mm, PEEQ P2 {g2['peeq'][-1]:.3e}")
e, el, layers = U.energies(out)
k = e["kinetic"][-1]/e["external"][-1]; i = int(np.argmax(e["kinetic"]))
print(f"energies at end: kinetic {100*k:.1f} %, elastic {100*e['elastic'][-1]/e['external'][-1]:.1f} %, plastic {100*e['plastic'][-1]/e['external'][-1]:.1f} %; at kinetic peak ({e['t'][i]*1e3:.2f} ms) {100*e['kinetic'][i]/e['external'][i]:.1f} %; external at 0.97/1.72/3.09 ms:",
      [round(float(np.interp(x, e["t"], e["external"]))*2*np.pi/1e6, 3) for x in (0.97e-3, 1.72e-3, 3.09e-3)], "MJ; balance error end", e['balance_error'][-1]/e['external'][-1])
