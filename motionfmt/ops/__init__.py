"""Operations on lossless documents, one per module, each the library side of one command.

Every operation takes :class:`~motiontool.motionfmt.document.MotionDocument` inputs and returns a
new document with a report of what it did (the inputs are not modified). Lines and cells it
keeps keep their spelling (spacing, ``+0.1``, digits, CRLF); new poses and changed numbers are
spelt canonically (shortest round-trip repr), so every value is the exact double intended.

* :mod:`~motiontool.motionfmt.ops.mirror`: swap left and right (``motiontool mirror``).
* :mod:`~motiontool.motionfmt.ops.concat`: play motions one after another (``concat``).
* :mod:`~motiontool.motionfmt.ops.trim`: keep a time window (``trim``).
* :mod:`~motiontool.motionfmt.ops.scale`: scale the excursions (``scale``).

What they share: :mod:`~motiontool.motionfmt.ops._cells` (lines and cells as bytes, and what an
operation gives back); mirror's arithmetic on text (negating and rearranging cells) is in
:mod:`~motiontool.motionfmt.ops.mirror`.

Import each operation from its module (``from motiontool.motionfmt.ops.mirror import mirror``):
this package re-exports nothing, so that ``ops.mirror`` is always the module, never the
function of the same name.

Pure numpy: robot knowledge (mirror maps, limits) comes in as plain mappings.

May import the rest of ``motionfmt`` and the top-level modules, as ``motionfmt`` may.
"""
