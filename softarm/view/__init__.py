"""Viewing: Rerun timelines (the live training view, replays), filmstrip PNGs and the pixel conventions
they share. The only stage that imports rerun or PIL; it draws what the other stages computed."""
