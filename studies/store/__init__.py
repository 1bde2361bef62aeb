"""The results store: content-addressed pieces on disk, their provenance, safe file writes, and reading a study's
results back (:mod:`studies.store.results`).

- :mod:`studies.store.cache`: :class:`~studies.store.cache.ResultStore` (keys, atomic entries, corruption checks);
- :mod:`studies.store.provenance`: code versions (part of every key) and provenance records;
- :mod:`studies.store.files`: atomic writes and generated-file markers;
- :mod:`studies.store.rom_export`: a ROM as ``.npz`` / ``.mat``;
- :mod:`studies.store.results`: :func:`~studies.store.results.load_results` and the result records.
"""
