"""Tools that evaluate the renderer, kept out of the library core: the stress suite on extreme scenes
(`restircl stress`), error against run time (`restircl report`), benchmarks (`restircl bench`) and the Cycles
bridge. The core package never imports this one (tests/eval/test_eval_imports.py)."""
