"""Split-specific lowering, one module per split (see `lower.py`, the dispatcher).

Each module's `lower(triple: Triple) -> SplitLowering` turns one (law,
element) into its split's IR, flop counts, extra constants and symbol names,
or raises `SplitRefused` with the reason."""
