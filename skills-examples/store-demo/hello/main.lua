-- Answers a greeting.
marvin.on("greet", function(request)
  marvin.say("Hello! I am Marvin.")
end)
