"""The ``[loads]`` section: certification gust loads (CS-25.341) of the study's aerofoil at flight points."""
