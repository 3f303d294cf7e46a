"""pipeplug scene: scene files (TOML) run through the FMU."""
