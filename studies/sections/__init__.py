"""Study sections: each part of a study in its own folder, behind one protocol (:mod:`studies.sections.protocol`).

- :mod:`studies.sections.gust_rom`: the paper's pipeline (steady flow, LFD FRFs, LTD histories, identified ROMs and
  their gust histories), always on;
- :mod:`studies.sections.aeroelastic`: ``[aeroelastic]``, flutter and gust response of typical sections;
- :mod:`studies.sections.nonlinear`: ``[nonlinear]``, nonlinear marches against the linear models;
- :mod:`studies.sections.loads`: ``[loads]``, certification gust loads (CS-25.341) at flight points from the ROMs.

Each folder holds the section's schema (its table and piece keys), its tasks and plan, its reader and its report
part, and a ``section`` module whose :class:`~studies.sections.protocol.Section` registers itself on import. The
registry imports the modules of :data:`BUILTIN` on first use (then the entry points of the group
``lfdrom.sections``), so that this package stays light to import.
"""

BUILTIN = ("studies.sections.gust_rom.section", "studies.sections.aeroelastic.section",
           "studies.sections.nonlinear.section", "studies.sections.loads.section")
"""The built-in sections' modules, in the order of their parts in the report page."""
