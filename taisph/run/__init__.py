"""The run loop and its writers: :mod:`.simulation` (``Simulation``: device state and
the loop that advances it), :mod:`.vtk` (ParaView frames), :mod:`.checkpoint`
(checkpoints and restarts), :mod:`.progress` (the progress bar and the run summary)."""
