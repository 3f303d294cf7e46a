"""Rigid models I and II: closed-form motion pieces, the exact event-driven solver, the paper's
explicit scheme."""
