"""Readers and writers: ParaView frames, checkpoints, the seed's text files, progress."""
