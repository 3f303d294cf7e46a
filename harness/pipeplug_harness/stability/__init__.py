"""pipeplug stability: the catalogue of hard cases, run on every solver."""
