"""GR(1) synthesis on BDDs (dd): realizability, strategies, explanations, export."""
