-- Hello and about: greets the user by name (asking for it the first time) and says what
-- the robot is. Shows marvin.on, marvin.say, marvin.ask and marvin.storage.

-- "anna maria" -> "Anna Maria"
local function capitalize(words)
  return (words:gsub("(%a)(%w*)", function(first, rest) return first:upper() .. rest end))
end

-- Answers come as the user said them: "my name is anna", "I'm Anna", "anna".
local function name_from(answer)
  local name = answer:lower()
  name = name:gsub("^%s*my name is%s+", ""):gsub("^%s*i am%s+", ""):gsub("^%s*i'm%s+", "")
  name = name:gsub("^%s+", ""):gsub("[%s%.!]+$", "")
  return capitalize(name)
end

marvin.on("hello", function()
  local name = marvin.storage.get("name")
  if not name then
    name = name_from(marvin.ask("Hello! I am Marvin. What is your name?"))
    if name == "" then
      marvin.say("Hello! How can I help?")
      return
    end
    marvin.storage.set("name", name)
  end
  marvin.say("Hello " .. name .. "! How can I help?")
end)

marvin.on("about", function()
  marvin.say("I am Marvin, a home robot. I can remind you of your medicine, remember where "
    .. "you put things, and answer simple questions. Everything stays here at home.")
end)

marvin.on("my_name", function(slots)
  local name = name_from(slots.name)
  marvin.storage.set("name", name)
  marvin.say("Nice to meet you, " .. name .. ".")
end)
