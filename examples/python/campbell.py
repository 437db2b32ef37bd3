"""The Campbell diagram of the reference rotor: whirl branches, critical speeds, a table.

Run from the repository's root: python examples/python/campbell.py
"""

import whirl

model = whirl.Model.from_file("examples/reference_rotor.toml")
diagram = whirl.campbell(model, "0:800Hz:161", orders=[1, 2])
for c in diagram.critical_speeds:
    print(f"critical speed {c.speed_hz:8.2f} Hz: branch {c.branch} x {c.order}X, zeta {c.damping_ratio:.4f}")
table = diagram.to_pandas()  # the CLI's campbell.csv
print(table[["speed_hz", "1F_frequency_hz", "1B_frequency_hz"]].iloc[::40])
