"""TODO eval/report"""
