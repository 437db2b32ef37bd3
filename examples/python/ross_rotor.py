"""A rotor from ROSS: a file saved by ROSS's Rotor.save (here the one the tests use), or,
with ROSS installed, a live ross.Rotor through whirl.from_ross.

Run from the repository's root: python examples/python/ross_rotor.py
"""

import whirl

model = whirl.read_ross("crates/whirl/tests/fixtures/ross/rotor_example_eb.toml")
print(model)
print("undamped frequencies [Hz]:", whirl.check(model).frequencies_hz.round(3))
try:
    import ross
except ImportError:
    print("(ROSS is not installed: whirl.from_ross(ross.rotor_example()) would read a live rotor)")
else:
    live = whirl.from_ross(ross.rotor_example(), name="rotor_example")
    print("from a live ross.Rotor:", whirl.check(live).frequencies_hz.round(3))
