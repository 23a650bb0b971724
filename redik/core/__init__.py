"""The foundation every other layer stands on: errors and warnings
(:mod:`~redik.core.exceptions`), the conventions written once (:mod:`~redik.core.conventions`:
frames, twist order, units, quaternion order), result records (:mod:`~redik.core.result`) and
argument checks (:mod:`~redik.core.validate`). Nothing here imports another part of redik.
"""
