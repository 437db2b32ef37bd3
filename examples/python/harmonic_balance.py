"""The synchronous response of the reference rotor by harmonic balance through its first
resonance: the branch with its Floquet stability, the bifurcation where stability is lost,
and the figure of the harmonics along the branch.

Run from the repository's root: python examples/python/harmonic_balance.py
"""

import os

import matplotlib

matplotlib.use("Agg")

import whirl  # noqa: E402
import whirl.plot  # noqa: E402

model = whirl.Model.from_file("examples/reference_rotor.toml")
result = whirl.hbm(model, "1:60Hz", harmonics=2, progress=False)
print(f"{result.points} points, {result.end}; bearings: {result.bearings}")
for b in result.bifurcations:
    print(f"{b['kind']} at {b['speed_hz']:.2f} Hz: stability {'lost' if b['loses_stability'] else 'regained'}")
branch = result.to_pandas("branch")  # the CLI's branch.csv
print(branch[["speed_hz", "stable", "n10_uy_1x_m"]].iloc[:: max(1, len(branch) // 8)])
os.makedirs("out", exist_ok=True)
whirl.plot.hb_branch(result).figure.savefig("out/hb_branch.png")
