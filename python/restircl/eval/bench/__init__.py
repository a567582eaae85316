"""TODO eval/bench"""
