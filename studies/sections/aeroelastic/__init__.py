"""The aeroelastic section of a study."""
