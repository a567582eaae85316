"""TODO eval/scenes"""
