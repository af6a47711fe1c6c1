"""Off-screen figures, drawn from arrays (never from files)."""
