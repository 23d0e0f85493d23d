"""The deformable (hysteretic) stop: its contact law, the integration of its contacts, the
reduced models of a mass pressed on it, and the solve that joins them (docs/physics.md,
"The deformable stop")."""
