"""Write engine_pressure.csv: the indicator diagram of the example engine (engine.toml),
the gauge pressure in the cylinder over the 720 degrees of a four-stroke cycle.

A textbook model, not a measurement: intake at 0.95 bar, polytropic compression
(n = 1.32) of the swept volume into the clearance (compression ratio 10) up to the
firing top dead centre at 360 deg, combustion by a Wiebe function (start 345 deg,
50 deg long) that multiplies the motored pressure by up to 4, polytropic expansion,
blow-down from 500 deg and exhaust at 1.1 bar. The crank angle theta is 0 at the top
dead centre that starts the intake stroke (the piston farthest from the crank, as in
engine.toml); the pressure is gauge, against 1 bar in the crankcase.

    python examples/engine_pressure.py     # rewrites examples/engine_pressure.csv
"""

from __future__ import annotations

import math
from pathlib import Path

R, L, BORE = 0.043, 0.1435, 0.086  # m: crank radius, rod, bore (as engine.toml)
RATIO, N = 10.0, 1.32  # compression ratio, polytropic exponent
P_IN, P_EXHAUST, P_CRANKCASE = 0.95, 1.10, 1.0  # bar
PEAK_FACTOR, START, LENGTH = 4.0, 345.0, 50.0  # combustion: factor, start and length [deg]
BLOWDOWN, EXHAUST = 500.0, 560.0  # deg: the exhaust valve opens, the pressure has fallen


def volume(theta_deg: float) -> float:
    """Cylinder volume [m3] at the crank angle (theta = 0: top dead centre)."""
    t = math.radians(theta_deg)
    travel = R * (1 - math.cos(t)) + L - math.sqrt(L * L - (R * math.sin(t)) ** 2)
    area = math.pi * BORE * BORE / 4
    clearance = area * 2 * R / (RATIO - 1)
    return clearance + area * travel


def burnt(theta_deg: float) -> float:
    """Wiebe's fraction of the charge burnt (a = 5, m = 2)."""
    if theta_deg <= START:
        return 0.0
    x = min((theta_deg - START) / LENGTH, 1.0)
    return 1.0 - math.exp(-5.0 * x ** 3)


def pressure(theta_deg: float) -> float:
    """Absolute pressure [bar] at the crank angle, 0 <= theta < 720."""
    if theta_deg < 180.0:
        return P_IN
    motored = P_IN * (volume(180.0) / volume(theta_deg)) ** N
    fired = motored * (1.0 + (PEAK_FACTOR - 1.0) * burnt(theta_deg))
    if theta_deg <= BLOWDOWN:
        return fired
    if theta_deg >= EXHAUST:
        return P_EXHAUST
    start = pressure(BLOWDOWN)
    s = (theta_deg - BLOWDOWN) / (EXHAUST - BLOWDOWN)
    return P_EXHAUST + (start - P_EXHAUST) * 0.5 * (1.0 + math.cos(math.pi * s))


def main() -> None:
    rows = ["theta_deg,value"]
    for k in range(360):  # every 2 deg over the cycle
        theta = 2.0 * k
        rows.append(f"{theta:g},{pressure(theta) - P_CRANKCASE:.6f}")
    Path(__file__).with_name("engine_pressure.csv").write_text("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
