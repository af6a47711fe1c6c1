"""tensegrity: six-strut tensegrity rolling robot simulation, kinematic workspace, locomotion."""
__version__ = "0.1.0"
