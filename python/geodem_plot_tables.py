"""The studies' table helpers, used by geodem_plot_studies.py and geodem_plot_calibrate.py.

The studied quantities' plain names and plotted units (QUANTITIES, quantity_info), numbers
that may be missing (finite, number), a CSV table as numpy columns (read_table) and a linear
fit as text (fit_text).
"""
import csv
import math

import numpy as np

# Studied quantities: a plain name, the factor to the plotted unit and that unit.
QUANTITIES = {
    "peak_q": ("peak deviator stress q", 1e-3, "kPa"),
    "sigma1_peak": ("peak major principal stress sigma1", 1e-3, "kPa"),
    "phi_peak_deg": ("peak friction angle", 1.0, "deg"),
    "phi_residual_deg": ("residual friction angle", 1.0, "deg"),
    "young_modulus": ("Young's modulus", 1e-6, "MPa"),
    "poisson_ratio": ("Poisson's ratio", 1.0, "-"),
    "dilatancy_deg": ("dilatancy angle", 1.0, "deg"),
    "axial_strain_at_peak": ("axial strain at the peak", 100.0, "%"),
    "cohesion": ("cohesion", 1e-3, "kPa"),
}


def quantity_info(name):
    """(plain name, factor to the plotted unit, unit, 'name (unit)' axis label)."""
    label, factor, unit = QUANTITIES.get(
        name, (name.replace("_", " "), 1.0, "deg" if name.endswith("_deg") else ""))
    return label, factor, unit, f"{label} ({unit})" if unit else label


def finite(x):
    """True for a number that is neither None, NaN nor infinite."""
    try:
        return x is not None and math.isfinite(float(x))
    except (TypeError, ValueError):
        return False


def number(x, default=float("nan")):
    return float(x) if finite(x) else default


def read_table(path):
    """Columns of a CSV file as numpy arrays (cells that are no numbers become NaN),
    or None when the file is absent or has no rows."""
    if not path.is_file():
        return None
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if len(rows) < 2:
        return None
    header = rows[0]
    cols = {name: [] for name in header}
    for row in rows[1:]:
        if len(row) != len(header):
            continue
        for name, cell in zip(header, row):
            try:
                cols[name].append(float(cell))
            except ValueError:
                cols[name].append(float("nan"))
    return {name: np.array(v, dtype=float) for name, v in cols.items()}


def fit_text(fit, factor, unit, variable):
    """'a unit + b unit variable, r2 = ...' for a {intercept, slope, r2} fit."""
    a, b = number(fit.get("intercept")), number(fit.get("slope"))
    r2 = number(fit.get("r2"))
    u = f" {unit}" if unit not in ("", "-") else ""
    text = f"{a * factor:.4g}{u} + {b * factor:.4g}{u} {variable}"
    if finite(r2):
        text += f", r2 = {r2:.3f}"
    return text

