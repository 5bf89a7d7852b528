"""Small simulated robots and action servers so every example runs without a robot."""
