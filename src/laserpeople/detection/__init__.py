"""laserpeople.detection"""
