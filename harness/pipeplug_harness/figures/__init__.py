"""pipeplug figures: the paper's figures redrawn from FMU runs."""
