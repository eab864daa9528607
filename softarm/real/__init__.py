"""Real robots: a lab's ROS 2 / Foxglove MCAP log made into a softarm recording (`import_log`), and a robot-style
log made from a softarm recording for tests and demos (`make_robot_log`)."""
