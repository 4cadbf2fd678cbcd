#!/usr/bin/env python3
"""Writes target_paints.csv: two SYNTHETIC paint reflectance spectra for detection-study targets.

No measured paint spectra are available to the project, so these are documented model curves,
not measurements; replace them with measured tables (same format) for real studies.

- camouflage_green: a conventional (not infrared-suppressing) green paint: dark blue and red
  (0.045), a green peak of 0.13 at 545 nm (Gaussian, 40 nm), and a plateau of 0.075 in the near
  infrared from a logistic step at 720 nm (20 nm wide), easing to 0.06 at 2500 nm. Leaves reflect
  about 0.45-0.5 there (PROSPECT), so the paint matches foliage in the visible but is dark in NIR:
  the classic detection case.
- painted_metal_grey: a mid-grey enamel on metal: 0.28 at 550 nm with a slight linear rise toward
  the infrared (0.02 per 1000 nm) and a small dip in the blue.

Run: python3 data/spectra/target_paints.py > data/spectra/target_paints.csv
"""
import math

print("# Synthetic paint reflectances (model curves, NOT measurements), written by target_paints.py;")
print("# see that script and data/README.md for the formulas and why they are synthetic.")
print("wavelength_nm,camouflage_green,painted_metal_grey")
for lam in range(350, 2501, 5):
    step = 1.0 / (1.0 + math.exp(-(lam - 720.0) / 20.0))
    green = 0.045 + 0.085 * math.exp(-(((lam - 545.0) / 40.0) ** 2)) + 0.03 * step
    green -= 0.015 * max(0.0, lam - 1000.0) / 1500.0
    grey = 0.28 + 0.02 * (lam - 550.0) / 1000.0 - 0.03 * math.exp(-(((lam - 400.0) / 40.0) ** 2))
    print(f"{lam},{green:.4f},{grey:.4f}")
