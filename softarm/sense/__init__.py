"""Sensing: what learning and imagination read from the stretch sensors: any node pairs, with realistic
imperfections. Recordings keep the ideal stretch; this stage models the rest downstream, so one recording
serves every sensor study.
"""
