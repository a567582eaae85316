"""TODO eval/stress"""
