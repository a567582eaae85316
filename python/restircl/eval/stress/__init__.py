"""`restircl stress`: the extreme cases (cases.py), their references (references.py), how a method is judged on
them (judging.py) and the suite runner (suite.py)."""
