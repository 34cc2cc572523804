"""Analyses that run many simulations or linearisations: natural modes (more to move here: stability, studies)."""
