"""The driver: check inputs once, then hand over to the method that fits the scene."""
