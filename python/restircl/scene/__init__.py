"""TODO scene"""
