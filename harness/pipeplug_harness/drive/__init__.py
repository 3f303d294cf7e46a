"""``pipeplug drive``: a whole drive, blow by blow, through one instance of the FMU."""
