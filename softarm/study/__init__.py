"""Comparative studies (`softarm study`): a grid of trials, each training a model on a shared corpus with its
own settings and scoring it on the held-out suite, run as Ray tasks, resumable, with a table and a plot.

From a notebook::

    from softarm.study.scale import QUICK
    done = softarm.run_study("sensors", "studies/sensors", QUICK)   # or a TOML file of trials
    print(done.markdown.read_text())

The study's folder holds corpus/ and suite/ (built once), trials/<name>.pt, trials.jsonl (one line per
finished trial: what a rerun skips), results.json, results.md and <study>.png (rewritten as trials finish).
"""
