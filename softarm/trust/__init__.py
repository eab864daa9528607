"""How far to trust what the arm imagines, in one room: the confidence (how right an imagined frame is likely to
be, each way of measuring it one class), the surprise (the body did what the command and the sensors' history
did not predict) with its memory check and alarm, their fits, their scores on the suite and their plot.

It reads the model's answers (`softarm.model.prediction`); `softarm.imagine` answers with it, `softarm.learn`
fits it from a training (`learn/trust_fits.py` gathers the data), `softarm.suite` scores it.
"""
