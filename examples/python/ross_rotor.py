"""A rotor from ROSS: a file saved by ROSS's Rotor.save (here the one the tests use), or,
with ROSS installed, a live ross.Rotor through whirl.from_ross; then given an unbalance
and, in place of its linear bearings, roller bearings with clearance.

Run from the repository's root: python examples/python/ross_rotor.py
"""

import whirl

model = whirl.read_ross("crates/whirl/tests/fixtures/ross/rotor_example_eb.toml")
print(model)
print("undamped frequencies [Hz]:", whirl.check(model).frequencies_hz.round(3))

# An unbalance on the disk at node 2, and the unbalance response there.
unbalanced = model.extended([whirl.Unbalance(node=2, mass="1 g", eccentricity="50 mm")])
peaks = whirl.unbalance(unbalanced, "1:200Hz:400", nodes=[2]).node(2).peaks
print("unbalance response peaks at node 2 [Hz]:", [round(p.speed_hz, 2) for p in peaks])

# Roller bearings with 20 um clearance where ROSS had linear bearings.
linear = [p for p in unbalanced.parts() if isinstance(p, whirl.Bearing)]
roller = whirl.Model.from_file("examples/reference_rotor.toml").to_tables()["roller_bearing"][0]
rollers = [whirl.RollerBearing(**{**roller, "name": f"roller {b.node}", "node": b.node}) for b in linear]
on_rollers = whirl.Model.build(model.name, [p for p in unbalanced.parts() if p not in linear] + rollers)
print("on roller bearings, undamped frequencies [Hz]:", whirl.check(on_rollers).frequencies_hz.round(3))
try:
    import ross
except ImportError:
    print("(ROSS is not installed: whirl.from_ross(ross.rotor_example()) would read a live rotor)")
else:
    live = whirl.from_ross(ross.rotor_example(), name="rotor_example")
    print("from a live ross.Rotor:", whirl.check(live).frequencies_hz.round(3))
