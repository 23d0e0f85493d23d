"""Numerical building blocks shared by the integrating methods (:mod:`core.switch`,
:mod:`core.event_method`): Runge-Kutta tableaux and steps, step-size control, cubic Hermite
interpolation and root finding on a step, and the work limits of a solve."""
