"""pipeplug cost: what accuracy costs in time, for every method."""
