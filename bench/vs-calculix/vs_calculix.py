#!/usr/bin/env python3
"""thermocontact against CalculiX 2.20 on CalculiX's "slide" style problem (issue 22).

    bench/vs-calculix/vs_calculix.py [--binary B] [--ccx CCX] [--refinements 1,2,3] [--r4]
        [--timeout 600] [--workdir DIR] [--step 0.01] [--ccx-max-increment S]
        [--scheme dynamic|quasistatic] [--only ours|ccx] [--busy N] [--default-threads]

Two steel blocks: the lower 2 x 1 x 0.5 mm (8r x 4r x 2r Hex8/C3D8 cells), the upper
1 x 0.5 x 0.5 mm centred on it (6r x 3r x 2r cells). The lower block's bottom is clamped and
held at 293.15 K; the upper block's top face is pressed down 0.5 um in 1 s, then slid 0.3 mm
along x in 1 s (prescribed displacements). Coulomb friction 0.3, gap conductance linear in the
contact pressure, frictional heat split 1/2 - 1/2, thermal expansion, adiabatic elsewhere,
200 time steps of 0.01 s in both programs (--step changes both).

For each refinement r the script writes a CalculiX deck (mm, N, s, t, K) and the equivalent
thermocontact case (SI), runs both in the same command on the same machine, one after the
other, each single-threaded, and prints per r: nodes, wall time of each (the process as a
user starts it, output included), the ratio ccx/ours and T/N in full slip from each
(thermocontact: history.csv contact_tangential_force / contact_normal_force; CalculiX: the
total reaction force on the upper block's top face, *NODE PRINT TOTALS=ONLY, which equals the contact
force here (no body forces, negligible inertia); the contact force from
*CONTACT PRINT CF is parsed as a cross-check where CalculiX writes it).

Choices where the issue is silent:
- Dynamic, as CalculiX: a transient *COUPLED TEMPERATURE-DISPLACEMENT step is a dynamic
  analysis in CalculiX (it sets nmethod = 4, prints "Dynamic analysis was selected",
  assembles the mass matrix and integrates with HHT, alpha = -0.05 by default; the heat
  equation by backward Euler), so thermocontact runs `scheme = "dynamic"` (Newmark average
  acceleration, backward Euler) with its default contact scheme. On these millimetre steel
  blocks inertia is negligible at tau = 0.01 s (rho h^2 / (E tau^2) ~ 1e-11), so the
  quasistatic scheme solves the same problem to that order; `--scheme quasistatic` runs it.
- Increments in CalculiX: automatic, starting at and never above our tau (--step, 0.01 s), so
  CalculiX takes the same 200 steps where it converges and cuts back where it does not.
  Fixed increments (DIRECT) diverge at the onset of sliding (t = 1.01 s), and with
  CalculiX's default controls the automatic incrementation fails there too ("too many
  cutbacks"); the deck allows more Newton iterations per increment (*CONTROLS, I_0 = 20,
  I_R = 30) and ten cutbacks, with which it takes exactly the 200 increments.
- Thermoelastic (Gough-Joule) heating off in thermocontact: CalculiX's coupled analysis has no
  such term.
- Conductance: thermocontact's gamma_C^s = gamma_C^m = 2.5e-3 W/(m^2 K Pa) give
  beta_C = 1.25e-3 W/(m^2 K Pa) (h = beta_C p) and delta_C = 0.5; in CalculiX
  *GAP CONDUCTANCE is the same line h(p) = 1.25 mW/(mm^2 K) per MPa (tabulated to 1e6 MPa)
  and *GAP HEAT GENERATION splits the heat 0.5 / 0.5.
- Contact in CalculiX: face-to-face penalty (TYPE=SURFACE TO SURFACE, linear
  pressure-overclosure with slope 50 E / h_slave, stick slope a tenth of it), the
  formulation that carries the gap conductance and the frictional heat in CalculiX; mortar
  (exact constraints, dual basis) in thermocontact. Slave: the upper block's bottom (the finer
  mesh) in both.
- Field output every 10 steps in both (thermocontact `.vtu`, CalculiX `.frd` U, NT);
  forces every step in history.csv, every 10th increment in CalculiX's .dat (CalculiX
  applies the *NODE FILE frequency to the prints too).
"""
import argparse
import csv
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# geometry [mm]
LOWER = ((-1.0, 1.0), (-0.5, 0.5), (-0.5, 0.0))
UPPER = ((-0.5, 0.5), (-0.25, 0.25), (0.0, 0.5))
PRESS = 0.5e-3  # mm, in 1 s
SLIDE = 0.3  # mm, in the next 1 s
FRICTION = 0.3
STEP = 0.01  # s: the default time step of both (--step)
END = 2.0  # s
THETA0 = 293.15  # K
GAMMA = 2.5e-3  # gamma_C^s = gamma_C^m [W/(m^2 K Pa)] -> beta_C = GAMMA/2, delta_C = 1/2
# steel
E_MPA = 210000.0
NU = 0.3
RHO = 7850.0  # kg/m^3
KAPPA = 50.0  # W/(m K)
CP = 450.0  # J/(kg K)
ALPHA = 1.2e-5  # 1/K


def cells(r):
    return (8 * r, 4 * r, 2 * r), (6 * r, 3 * r, 2 * r)


def node_count(r):
    lo, up = cells(r)
    return math.prod(c + 1 for c in lo) + math.prod(c + 1 for c in up)


# --- CalculiX deck (mm, N, s, t, K) -------------------------------------------------------
def box(first_node, first_elem, lim, n):
    """Nodes and C3D8 elements of a box; returns (nodes, elems, faces) with faces[name]
    the list of (elem, face id) and node sets by face name."""
    nx, ny, nz = n
    nid = lambda i, j, k: first_node + i + (nx + 1) * (j + (ny + 1) * k)
    nodes = []
    for k in range(nz + 1):
        for j in range(ny + 1):
            for i in range(nx + 1):
                x = lim[0][0] + (lim[0][1] - lim[0][0]) * i / nx
                y = lim[1][0] + (lim[1][1] - lim[1][0]) * j / ny
                z = lim[2][0] + (lim[2][1] - lim[2][0]) * k / nz
                nodes.append((nid(i, j, k), x, y, z))
    elems, bottom, top = [], [], []
    e = first_elem
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                # C3D8: 1-4 counter-clockwise at the bottom, 5-8 above them: face S1 is
                # z-min (1-2-3-4), S2 is z-max (5-8-7-6)
                elems.append((e, nid(i, j, k), nid(i + 1, j, k), nid(i + 1, j + 1, k),
                              nid(i, j + 1, k), nid(i, j, k + 1), nid(i + 1, j, k + 1),
                              nid(i + 1, j + 1, k + 1), nid(i, j + 1, k + 1)))
                if k == 0:
                    bottom.append(e)
                if k == nz - 1:
                    top.append(e)
                e += 1
    nset_bottom = [nid(i, j, 0) for j in range(ny + 1) for i in range(nx + 1)]
    nset_top = [nid(i, j, nz) for j in range(ny + 1) for i in range(nx + 1)]
    return nodes, elems, bottom, top, nset_bottom, nset_top


def id_lines(ids, per_line=8):
    return "\n".join(", ".join(str(i) for i in ids[k:k + per_line])
                     for k in range(0, len(ids), per_line))


def calculix_deck(r, step, max_increment):
    lo, up = cells(r)
    n_lower = math.prod(c + 1 for c in lo)
    e_lower = math.prod(lo)
    ln, le, _, l_top, l_nbot, _ = box(1, 1, LOWER, lo)
    un, ue, u_bot, _, _, u_ntop = box(n_lower + 1, e_lower + 1, UPPER, up)
    h_slave = (UPPER[0][1] - UPPER[0][0]) / up[0]
    k_normal = 50.0 * E_MPA / h_slave  # N/mm^3
    beta = GAMMA / 2 * 1e3  # mW/(mm^2 K) per MPa
    p_max = 1e6  # MPa
    out = []
    w = out.append
    w(f"** thermocontact bench/vs-calculix, r = {r}: two steel blocks, slide with friction")
    w("** units: mm, N, s, t, K (energy mJ, power mW)")
    w("*NODE, NSET=NALL")
    for n in ln + un:
        w(f"{n[0]}, {n[1]:.12g}, {n[2]:.12g}, {n[3]:.12g}")
    w("*ELEMENT, TYPE=C3D8, ELSET=ELOWER")
    for e in le:
        w(", ".join(str(v) for v in e))
    w("*ELEMENT, TYPE=C3D8, ELSET=EUPPER")
    for e in ue:
        w(", ".join(str(v) for v in e))
    w("*NSET, NSET=NBOT")
    w(id_lines(l_nbot))
    w("*NSET, NSET=NTOP")
    w(id_lines(u_ntop))
    w("*ELSET, ELSET=ESLAVE")
    w(id_lines(u_bot))
    w("*ELSET, ELSET=EMASTER")
    w(id_lines(l_top))
    w("*SURFACE, NAME=SLAVE, TYPE=ELEMENT")
    w("ESLAVE, S1")
    w("*SURFACE, NAME=MASTER, TYPE=ELEMENT")
    w("EMASTER, S2")
    w("*MATERIAL, NAME=STEEL")
    w("*ELASTIC")
    w(f"{E_MPA:g}, {NU:g}")
    w("*DENSITY")
    w(f"{RHO * 1e-12:.6g}")  # t/mm^3
    w(f"*EXPANSION, ZERO={THETA0:g}")
    w(f"{ALPHA:g}")
    w("*CONDUCTIVITY")
    w(f"{KAPPA:g}")  # W/(m K) = mW/(mm K)
    w("*SPECIFIC HEAT")
    w(f"{CP * 1e6:.6g}")  # J/(kg K) = mm^2/(s^2 K)
    w("*SOLID SECTION, ELSET=ELOWER, MATERIAL=STEEL")
    w("*SOLID SECTION, ELSET=EUPPER, MATERIAL=STEEL")
    w("*SURFACE INTERACTION, NAME=SI")
    w("*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR")
    w(f"{k_normal:.6g}")
    w("*FRICTION")
    w(f"{FRICTION:g}, {k_normal / 10:.6g}")
    w("*GAP CONDUCTANCE")  # conductance, pressure: h = beta p
    w(f"0., 0., {THETA0:g}")
    w(f"{beta * p_max:.6g}, {p_max:.6g}, {THETA0:g}")
    w("*GAP HEAT GENERATION")  # all dissipation to heat, half to the slave, slip velocity
    w("1., 0.5, -1.")
    w("*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE")
    w("SLAVE, MASTER")
    w("*AMPLITUDE, NAME=APRESS, TIME=TOTAL TIME")
    w(f"0., 0., 1., 1., {END:g}, 1.")
    w("*AMPLITUDE, NAME=ASLIDE, TIME=TOTAL TIME")
    w(f"0., 0., 1., 0., {END:g}, 1.")
    w("*INITIAL CONDITIONS, TYPE=TEMPERATURE")
    w(f"NALL, {THETA0:g}")
    w(f"*STEP, INC={10 * round(END / step)}")
    # more Newton iterations before a cutback (I_0 = 20, I_R = 30, ..., I_A = 10 cutbacks):
    # with CalculiX's defaults the stick-slip transition at t = 1 s fails in ten cutbacks
    w("*CONTROLS, PARAMETERS=TIME INCREMENTATION")
    w("20, 30, 9, 200, 10, 4, , 10")
    # automatic incrementation: initial increment tau, at most tau (fixed increments of tau,
    # DIRECT, diverge at the onset of sliding, t = 1.01 s); --ccx-max-increment widens it
    w("*COUPLED TEMPERATURE-DISPLACEMENT")
    w(f"{step:g}, {END:g}, {step * 1e-4:g}, {max_increment:g}")
    w("*BOUNDARY")
    w("NBOT, 1, 3, 0.")
    w(f"NBOT, 11, 11, {THETA0:g}")
    w("NTOP, 2, 2, 0.")
    w("*BOUNDARY, AMPLITUDE=APRESS")
    w(f"NTOP, 3, 3, {-PRESS:g}")
    w("*BOUNDARY, AMPLITUDE=ASLIDE")
    w(f"NTOP, 1, 1, {SLIDE:g}")
    w("*NODE PRINT, NSET=NTOP, TOTALS=ONLY")
    w("RF")
    w("*CONTACT PRINT, SLAVE=SLAVE, MASTER=MASTER")
    w("CF")
    w("*NODE FILE, FREQUENCY=10")
    w("U, NT")
    w("*END STEP")
    return "\n".join(out) + "\n"


# --- thermocontact case (SI) ---------------------------------------------------------------
def thermocontact_case(r, scheme, step):
    lo, up = cells(r)
    mm = 1e-3
    lim = lambda b: (f"min = [{b[0][0] * mm:g}, {b[1][0] * mm:g}, {b[2][0] * mm:g}], "
                     f"max = [{b[0][1] * mm:g}, {b[1][1] * mm:g}, {b[2][1] * mm:g}]")
    return f"""# bench/vs-calculix, r = {r}: the CalculiX deck slide.inp beside this file, in SI.
# CalculiX's transient *COUPLED TEMPERATURE-DISPLACEMENT is dynamic (mass matrix, HHT) with
# backward Euler in the temperature: "dynamic" here (inertia is negligible at this size and
# step either way: bench/vs-calculix/vs_calculix.py).
title = "vs CalculiX: two steel blocks, slide with friction, r = {r}"
dimension = 3

[time]
scheme = "{scheme}"
step = {step:g}
end = {END:g}

[physics]
reference_temperature = {THETA0:g}
thermal_expansion = true
thermoelastic_heating = false   # CalculiX's coupled analysis has no Gough-Joule term

[materials.steel]
density = {RHO:g}
young_modulus = {E_MPA * 1e6:g}
poisson_ratio = {NU:g}
thermal_expansion = {ALPHA:g}
specific_heat = {CP:g}
thermal_conductivity = {KAPPA:g}

[[bodies]]
name = "lower"
material = "steel"
mesh = {{ box = {{ {lim(LOWER)}, cells = [{lo[0]}, {lo[1]}, {lo[2]}] }} }}

[[bodies]]
name = "upper"
material = "steel"
mesh = {{ box = {{ {lim(UPPER)}, cells = [{up[0]}, {up[1]}, {up[2]}] }} }}

[[boundary]]
body = "lower"
where = "zmin"
displacement = [0.0, 0.0, 0.0]
temperature = {THETA0:g}

[[boundary]]
body = "upper"
where = "zmax"
displacement = [{{ t = [0.0, 1.0, {END:g}], value = [0.0, 0.0, {SLIDE * mm:g}] }},
                0.0,
                {{ t = [0.0, 1.0], value = [0.0, {-PRESS * mm:g}] }}]

[contact]
slave = {{ body = "upper", where = "zmin" }}
master = {{ body = "lower", where = "zmax" }}
friction = {FRICTION:g}
conductance = {{ slave = {GAMMA:g}, master = {GAMMA:g} }}   # beta_C = {GAMMA / 2:g}, delta_C = 0.5
heat_conduction = true
frictional_heating = true

[output]
directory = "out"
every = 10
"""


# --- runs ----------------------------------------------------------------------------------
def single_thread_env():
    env = dict(os.environ)
    for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "CCX_NPROC_EQUATION_SOLVER",
              "CCX_NPROC_RESULTS", "CCX_NPROC_STIFFNESS"):
        env[k] = "1"
    return env


def run_ours(binary, workdir, timeout, default_threads=False):
    case = os.path.join(workdir, "case.toml")
    out = os.path.join(workdir, "out")
    t0 = time.perf_counter()
    env = single_thread_env()
    if default_threads:
        env.pop("OPENBLAS_NUM_THREADS")
        env.pop("OMP_NUM_THREADS")
    p = subprocess.run([binary, "run", case, "--output", out, "--force"], capture_output=True,
                       text=True, env=env, timeout=timeout)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        raise RuntimeError(f"thermocontact failed ({p.returncode}): "
                           + (p.stdout + p.stderr).strip()[-500:])
    rows = list(csv.DictReader(open(os.path.join(out, "history.csv"))))
    return wall, rows


NUM = r"[-+]?\d*\.?\d+(?:[eE][-+]?\d+)?"


def run_ccx(ccx, workdir, timeout):
    """(wall, forces, error); the log goes to ccx.log as CalculiX writes it, so a run stopped
    at the timeout still says how far it got."""
    log_path = os.path.join(workdir, "ccx.log")
    t0 = time.perf_counter()
    with open(log_path, "w") as log:
        try:
            p = subprocess.run([ccx, "-i", "slide"], cwd=workdir, stdout=log,
                               stderr=subprocess.STDOUT, env=single_thread_env(),
                               timeout=timeout)
        except subprocess.TimeoutExpired:
            reached = re.findall(r"actual total time=\s*(" + NUM + ")", open(log_path).read())
            at = f", at t = {float(reached[-1]):.3g} of {END:g} s" if reached else ""
            dat = os.path.join(workdir, "slide.dat")
            return None, parse_dat(dat) if os.path.exists(dat) else None, \
                f"> {timeout:g} (stopped{at})"
    wall = time.perf_counter() - t0
    out = open(log_path).read()
    if p.returncode != 0 or "*ERROR" in out:
        lines = [x for x in out.splitlines() if x.strip()]
        return None, None, "ccx failed: " + " | ".join(lines[-3:])
    return wall, parse_dat(os.path.join(workdir, "slide.dat")), None




def parse_dat(path):
    """{time: (T, N)} from the total reaction force on NTOP, and the same from the contact
    force statistics (CF) where present, as {'rf': {...}, 'cf': {...}}."""
    rf, cf = {}, {}
    lines = open(path).read().splitlines()
    i = 0
    while i < len(lines):
        s = lines[i]
        m = re.search(r"total force \(fx,fy,fz\) for set NTOP and time\s+(" + NUM + ")", s)
        if m:
            j = i + 1
            while j < len(lines) and not lines[j].strip():
                j += 1
            f = [float(v) for v in re.findall(NUM, lines[j])[-3:]]
            rf[float(m.group(1))] = (math.hypot(f[0], f[1]), abs(f[2]))
            i = j
        m = re.search(r"statistics for slave set .* and time\s+(" + NUM + ")", s)
        if m:
            t = float(m.group(1))
            # the block lists the total surface force (fx,fy,fz) (and moments) first
            for j in range(i + 1, min(i + 12, len(lines))):
                if "total surface force" in lines[j]:
                    k = j + 1
                    while k < len(lines) and not lines[k].strip():
                        k += 1
                    f = [float(v) for v in re.findall(NUM, lines[k])[:3]]
                    cf[t] = (math.hypot(f[0], f[1]), abs(f[2]))
                    break
        i += 1
    return {"rf": rf, "cf": cf}


def slip_ratio(pairs):
    """T/N over the sliding phase once slip is established (t >= 1.5 s): (last, min, max)."""
    vals = [t / n for tt, (t, n) in sorted(pairs) if tt >= 1.5 - 1e-9 and n > 0]
    if not vals:
        return None
    return vals[-1], min(vals), max(vals)


def fmt_ratio(r):
    return "—" if r is None else f"{r[0]:.4f} ({r[1]:.4f}–{r[2]:.4f})"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--binary", default=os.path.join(ROOT, "build/bin/thermocontact"))
    ap.add_argument("--ccx", default=shutil.which("ccx") or "ccx")
    ap.add_argument("--refinements", default="1,2,3")
    ap.add_argument("--r4", action="store_true", help="add r = 4 (CalculiX: ~10 min or more)")
    ap.add_argument("--timeout", type=float, default=600.0, help="per run [s]")
    ap.add_argument("--workdir", help="keep decks, cases and outputs here (default: a temporary "
                    "directory, removed at the end)")
    ap.add_argument("--step", type=float, default=STEP,
                    help="time step of both [s]: our tau, CalculiX's first and largest "
                    "increment (default 0.01: 200 steps)")
    ap.add_argument("--ccx-max-increment", type=float,
                    help="CalculiX's largest increment [s] (default: --step)")
    ap.add_argument("--scheme", choices=["dynamic", "quasistatic"], default="dynamic",
                    help="thermocontact's time scheme (default dynamic, as CalculiX's)")
    ap.add_argument("--only", choices=["ours", "ccx"], help="run one program only")
    ap.add_argument("--busy", type=int, default=0,
                    help="start N busy processes (`yes > /dev/null`) for the whole command: "
                    "issue 39's machine with other work on it")
    ap.add_argument("--default-threads", action="store_true",
                    help="run thermocontact with its default BLAS thread policy "
                    "(OPENBLAS_NUM_THREADS unset) instead of one thread")
    a = ap.parse_args()
    busy = [subprocess.Popen(["yes"], stdout=subprocess.DEVNULL) for _ in range(a.busy)]
    try:
        compare(a)
    finally:
        for p in busy:
            p.kill()


def compare(a):
    rs = [int(x) for x in a.refinements.split(",") if x]
    if a.r4 and 4 not in rs:
        rs.append(4)
    top = a.workdir or tempfile.mkdtemp(prefix="vs-calculix-")
    os.makedirs(top, exist_ok=True)
    print(f"binary: {a.binary}\nccx: {a.ccx}\nworkdir: {top}\nbusy processes: {a.busy}, "
          f"thermocontact threads: {'default policy' if a.default_threads else 1}",
          file=sys.stderr)
    print("| r | nodes | thermocontact [s] | CalculiX [s] | ratio ccx/ours | T/N ours at 2 s "
          "(1.5–2 s) | T/N CalculiX RF, last (from 1.5 s) | T/N CalculiX CF, last | N ours [N] | "
          "N CalculiX [N] | ours: steps, QP it. | CalculiX: increment attempts, Newton iterations |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rs:
        d = os.path.join(top, f"r{r}")
        os.makedirs(d, exist_ok=True)
        with open(os.path.join(d, "case.toml"), "w") as f:
            f.write(thermocontact_case(r, a.scheme, a.step))
        with open(os.path.join(d, "slide.inp"), "w") as f:
            f.write(calculix_deck(r, a.step, a.ccx_max_increment or a.step))
        cols = {k: "—" for k in ("ours", "ccx", "ratio", "tn", "tn_rf", "tn_cf", "n", "n_ccx",
                                 "it", "it_ccx")}
        ours = ccx = None
        if a.only != "ccx":
            ours, rows = run_ours(a.binary, d, a.timeout, a.default_threads)
            cols["ours"] = f"{ours:.2f}"
            cols["tn"] = fmt_ratio(slip_ratio(
                [(float(x["time"]), (float(x["contact_tangential_force"]),
                                     float(x["contact_normal_force"]))) for x in rows]))
            cols["n"] = f"{float(rows[-1]['contact_normal_force']):.4g}"
            cols["it"] = f"{rows[-1]['step']}, {sum(int(x['qp_iterations']) for x in rows)}"
        if a.only != "ours":
            ccx, res, err = run_ccx(a.ccx, d, a.timeout)
            cols["ccx"] = err if err else f"{ccx:.2f}"
            if res:  # a run stopped at the timeout: T/N up to where it got
                cols["tn_rf"] = fmt_ratio(slip_ratio(res["rf"].items()))
                tn_cf = slip_ratio(res["cf"].items())
                cols["tn_cf"] = "—" if tn_cf is None else f"{tn_cf[0]:.4f}"
                if res["rf"]:
                    cols["n_ccx"] = f"{res['rf'][max(res['rf'])][1]:.4g}"
            log = open(os.path.join(d, "ccx.log")).read() if os.path.exists(
                os.path.join(d, "ccx.log")) else ""
            cols["it_ccx"] = (f"{len(re.findall(r'^ increment .* attempt', log, re.M))}, "
                              f"{len(re.findall(r'^ iteration ', log, re.M))}")
        if ours and ccx:
            cols["ratio"] = f"{ccx / ours:.1f}×"
        elif ours and cols["ccx"].startswith(">"):  # stopped at the timeout: a lower bound
            cols["ratio"] = f"> {math.floor(a.timeout / ours)}×"
        print(f"| {r} | {node_count(r)} | {cols['ours']} | {cols['ccx']} | {cols['ratio']} | "
              f"{cols['tn']} | {cols['tn_rf']} | {cols['tn_cf']} | {cols['n']} | "
              f"{cols['n_ccx']} | {cols['it']} | {cols['it_ccx']} |", flush=True)
    if not a.workdir:
        shutil.rmtree(top, ignore_errors=True)


if __name__ == "__main__":
    main()
