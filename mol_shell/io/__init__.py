"""What users look at: 3-D export for ParaView (:mod:`.export`), animations (:mod:`.animate`) and
figures (:mod:`.figures`), all from a run's Dataset; :mod:`.fields` names what a run offers."""
