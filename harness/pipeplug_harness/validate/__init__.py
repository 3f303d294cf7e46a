"""pipeplug validate: the FMU against the closed form; FMI cross-check files."""
