#!/usr/bin/python3
"""The growth rates of example 10 against the sliding speed: every eigenvalue that
`thermocontact stability` wrote to stability.csv (dots), and the closed form of the half-plane
for the modes cos(n m x), n = 1, 2, 3 (lines): b_n = κ(nm)²(ℓ² − 1), ℓ(ℓ + 1) = 2V/(n V_cr)
(docs/theory.md, "Thermoelastic instability of a layer under a rigid flat").
  /usr/bin/python3 examples/10-tei-layer/plot_growth.py OUT/stability.csv [-o growth.png]
"""
import argparse
import csv
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

# Configuration T (case.toml): steel, 𝔉 = 0.1, half a wavelength W = 0.01 m.
k, rho, cp, e, nu, alpha, f = 50.0, 7850.0, 460.0, 2.0e11, 0.3, 1.2e-5, 0.1
m = math.pi / 0.01
kappa = k / (rho * cp)
v_cr = 2 * k * (1 - nu) * m / (f * e * alpha)
unit = kappa * m * m


def closed_form(r, n):
    """b_n/(κm²) at V/V_cr = r."""
    ell = (math.sqrt(1 + 8 * r / n) - 1) / 2
    return n * n * (ell * ell - 1)


ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
ap.add_argument("csv")
ap.add_argument("-o", "--output", default="growth.png")
a = ap.parse_args()
rows = list(csv.DictReader(open(a.csv)))
fig, ax = plt.subplots(figsize=(6.4, 4.2))
ax.plot([float(r["speed"]) / v_cr for r in rows], [float(r["re"]) / unit for r in rows], "k.",
        ms=4, label="thermocontact stability (FE, 20×90 Quad4)")
rs = [0.05 * i for i in range(1, 101)]
for n, style in ((1, "-"), (2, "--"), (3, ":")):
    ax.plot(rs, [closed_form(r, n) for r in rs], "C0" + style, lw=1.2,
            label=f"closed form, cos({n}mx)" if n > 1 else "closed form, cos(mx)")
ax.axhline(0, color="0.6", lw=0.8)
ax.axvline(1, color="0.6", lw=0.8)
ax.set_xlim(0, 5)
ax.set_ylim(-3, 10)
ax.set_xlabel("sliding speed V / V_cr  (V_cr = %.4f m/s)" % v_cr)
ax.set_ylabel("growth rate b / κm²")
ax.set_title("Thermoelastic instability of a steel layer under a sliding rigid flat")
ax.legend(loc="upper left", fontsize=8)
fig.tight_layout()
fig.savefig(a.output, dpi=120)
print("wrote", a.output)
