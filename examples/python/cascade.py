"""An NSV cascade of the reference rotor on its roller bearings, at two clearances (the
model edited by the study files' parameter paths), with its checkpoint.

Run from the repository's root: python examples/python/cascade.py
"""

import whirl

model = whirl.Model.from_file("examples/reference_rotor.toml")
for clearance in ("20 um", "60 um"):
    rotor = model.with_values({"roller_bearing[*].clearance": clearance})
    result = whirl.cascade(
        rotor, "100Hz:400Hz:8", no_refine=True, max_records=2, checkpoint="out/python-cascade.partial"
    )
    largest = result.to_dict()["nsv"]["largest"]
    print(
        f"clearance {clearance}: largest NSV {largest['amplitude_m'] * 1e6:.2f} um "
        f"at {largest['frequency_hz']:.1f} Hz when running at {largest['speed_hz']:.1f} Hz"
    )
nsv = result.to_pandas("nsv")  # the CLI's nsv.csv
print(nsv[["speed_hz", "one_x_m", "nsv_frequency_hz", "nsv_amplitude_m", "class"]])
