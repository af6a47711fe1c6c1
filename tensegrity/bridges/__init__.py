"""Bridges to the tools robotics users already use (issue 33): `mjcf`, the robot as a MuJoCo
model. Physics only (layer: physics, paper); MuJoCo itself is never imported here."""
