"""laserpeople.evaluation"""
