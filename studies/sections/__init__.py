"""Study sections: each part of a study (the gust-ROM pipeline, ``[aeroelastic]``, ``[nonlinear]``) in its own
folder."""
