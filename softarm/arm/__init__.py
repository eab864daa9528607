"""The arm: body geometry, drive, sensors and camera map, as plain NumPy (docs/model.md).

Everything the simulator, the recorder and the tests need to know about the arm is computed here,
once, from the config; `reference` is an independent float64 NumPy implementation of the model.
"""
