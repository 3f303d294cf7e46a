"""Friction contacts: the two-contact Coulomb projection (one pattern table) and the outer laws."""
