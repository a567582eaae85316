"""TODO eval/cycles"""
